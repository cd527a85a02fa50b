// labels.cpp - per-triangle pixel counts, the label rule, views, marking colours.
#include <cmath>
#include <stdexcept>
#include <string>

#include "perclod/raycast.h"

namespace perclod {

TriangleCounts count_triangles(const uint32_t* tri_plus_one, const uint8_t* mask, size_t pixel_count,
                               size_t triangle_count) {
  if (!tri_plus_one && pixel_count > 0)
    throw std::invalid_argument("count_triangles: triangle buffer is null");
  TriangleCounts c;
  c.traced.assign(triangle_count, 0);
  c.imperceptible.assign(triangle_count, 0);
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
  return c;
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
  for (size_t i = 0; i < n; ++i) {
    bool perceptible = false, displayed = false;
    for (const auto& view : views) {
      perceptible |= view[i] == Label::Perceptible;
      displayed |= view[i] != Label::Undisplayable;
    }
    out[i] = perceptible ? Label::Perceptible : displayed ? Label::Imperceptible : Label::Undisplayable;
  }
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
