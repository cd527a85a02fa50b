// labels.cpp - per-triangle pixel counts, the label rule, views, marking colours.
#include <cmath>
#include <stdexcept>
#include <string>

#include "perclod/raycast.h"

namespace perclod {

TriangleCounts count_triangles(const uint32_t* tri_plus_one, const uint8_t* mask, size_t pixel_count,
                               size_t triangle_count) {
  TriangleCounts c;
  c.traced.assign(triangle_count, 0);
  c.imperceptible.assign(triangle_count, 0);
  add_counts(c, tri_plus_one, mask, pixel_count);
  return c;
}

void add_counts(TriangleCounts& c, const uint32_t* tri_plus_one, const uint8_t* mask, size_t pixel_count) {
  if (!tri_plus_one && pixel_count > 0)
    throw std::invalid_argument("count_triangles: triangle buffer is null");
  if (c.traced.size() != c.imperceptible.size())
    throw std::invalid_argument("count_triangles: traced and imperceptible counts differ in size");
  const size_t triangle_count = c.traced.size();
  for (size_t p = 0; p < pixel_count; ++p) {
    const uint32_t id = tri_plus_one[p];
    if (id == 0) continue;
    if (id > triangle_count)
      throw std::invalid_argument("count_triangles: pixel " + std::to_string(p) + " names triangle " +
                                  std::to_string(id - 1) + " but the scene has " +
                                  std::to_string(triangle_count));
    ++c.traced[id - 1];
    if (mask && mask[p]) ++c.imperceptible[id - 1];
  }
}

std::vector<std::array<double, 2>> sample_offsets(int n) {
  switch (n) {
    case 1: return {{0.0, 0.0}};
    case 2: return {{-0.25, -0.25}, {0.25, 0.25}};
    case 4: return {{-0.125, -0.375}, {0.375, -0.125}, {-0.375, 0.125}, {0.125, 0.375}};
    case 8: {
      std::vector<std::array<double, 2>> s;
      for (auto [x, y] : {std::pair{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}})
        s.push_back({x / 16.0, y / 16.0});
      return s;
    }
    case 9: return grid_offsets(3);
    case 16: return grid_offsets(4);
  }
  throw std::invalid_argument("samples per pixel must be 1, 2, 4, 8, 9 or 16, not " + std::to_string(n));
}

std::vector<std::array<double, 2>> grid_offsets(int s) {
  if (s < 1 || s > 4) throw std::invalid_argument("sample grid must be 1 to 4 per axis, not " + std::to_string(s));
  std::vector<std::array<double, 2>> out;
  for (int b = 0; b < s; ++b)
    for (int a = 0; a < s; ++a) out.push_back({(a + 0.5) / s - 0.5, (b + 0.5) / s - 0.5});
  return out;
}

int sample_grid(int n) { return n == 9 ? 3 : n == 16 ? 4 : 0; }

void mark_in_frustum(const Scene& scene, const Camera& cam, std::vector<uint8_t>& inside) {
  const size_t nt = scene.triangle_count();
  if (inside.size() != nt) throw std::invalid_argument("mark_in_frustum: one entry per triangle expected");
  const double ty = cam.tan_half_y(), tx = ty * cam.aspect();
  // Per vertex: bit k set when outside plane k (near, far, left, right, bottom, top).
  const size_t nv = scene.positions.size() / 3;
  std::vector<uint8_t> out(nv);
  for (size_t v = 0; v < nv; ++v) {
    Eigen::Vector3d d(scene.positions[3 * v] - cam.eye.x(), scene.positions[3 * v + 1] - cam.eye.y(),
                      scene.positions[3 * v + 2] - cam.eye.z());
    const double z = d.dot(cam.forward), u = d.dot(cam.right), w = d.dot(cam.up);
    // The shifted frame moves the edges by at most a pixel: widen by one pixel.
    const double mx = z * tx * (1.0 + 2.0 / cam.width), my = z * ty * (1.0 + 2.0 / cam.height);
    out[v] = uint8_t((z < cam.znear) | (z > cam.zfar) << 1 | (u < -mx) << 2 | (u > mx) << 3 | (w < -my) << 4 |
                     (w > my) << 5);
  }
  for (size_t t = 0; t < nt; ++t) {
    if (inside[t]) continue;
    const uint32_t* i = &scene.indices[3 * t];
    if ((out[i[0]] & out[i[1]] & out[i[2]]) == 0) inside[t] = 1;
  }
}

std::vector<Label> label_triangles(const TriangleCounts& counts, double ratio) {
  if (!(ratio >= 0.0 && ratio <= 1.0))
    throw std::invalid_argument("label_triangles: ratio " + std::to_string(ratio) + " must lie in [0, 1]");
  if (counts.traced.size() != counts.imperceptible.size())
    throw std::invalid_argument("label_triangles: traced and imperceptible counts differ in size");
  std::vector<Label> labels(counts.traced.size());
  for (size_t i = 0; i < labels.size(); ++i) {
    const uint32_t traced = counts.traced[i], imp = counts.imperceptible[i];
    if (imp > traced)
      throw std::invalid_argument("label_triangles: triangle " + std::to_string(i) +
                                  " has more imperceptible than traced pixels");
    if (traced == 0)
      labels[i] = Label::Undisplayable;
    else  // imp / traced >= ratio, without rounding the quotient
      labels[i] = double(imp) >= ratio * double(traced) ? Label::Imperceptible : Label::Perceptible;
  }
  return labels;
}

std::vector<Label> combine_views(const std::vector<std::vector<Label>>& views) {
  if (views.empty()) throw std::invalid_argument("combine_views: no views");
  const size_t n = views[0].size();
  for (size_t v = 1; v < views.size(); ++v)
    if (views[v].size() != n)
      throw std::invalid_argument("combine_views: view " + std::to_string(v) + " has " +
                                  std::to_string(views[v].size()) + " labels, view 0 has " +
                                  std::to_string(n));
  std::vector<Label> out(n, Label::Undisplayable);
  for (const auto& view : views)
    for (size_t i = 0; i < n; ++i) out[i] = combine_labels(out[i], view[i]);
  return out;
}

LabelCounts count_labels(const std::vector<Label>& labels) {
  LabelCounts c;
  for (Label l : labels) {
    switch (l) {
      case Label::Perceptible: ++c.perceptible; break;
      case Label::Imperceptible: ++c.imperceptible; break;
      case Label::Undisplayable: ++c.undisplayable; break;
    }
  }
  return c;
}

std::array<float, 3> marking_color(Label label) {
  switch (label) {
    case Label::Perceptible: return {0.0f, 0.8f, 0.0f};
    case Label::Imperceptible: return {0.9f, 0.0f, 0.0f};
    case Label::Undisplayable: return {0.0f, 0.2f, 1.0f};
  }
  throw std::invalid_argument("marking_color: unknown label value");
}

std::vector<float> marking_colors(const std::vector<Label>& labels) {
  std::vector<float> rgb(3 * labels.size());
  for (size_t i = 0; i < labels.size(); ++i) {
    const auto c = marking_color(labels[i]);
    rgb[3 * i] = c[0];
    rgb[3 * i + 1] = c[1];
    rgb[3 * i + 2] = c[2];
  }
  return rgb;
}

}  // namespace perclod
