// perclod/scene.h - the flat triangle scene every module shares.
//
// A Scene is what the loader produces and what the renderer, the ray caster
// and the simplifier consume: one vertex array, one index array, and per
// triangle the component it belongs to and the material that colours it.
// Positions are float and recentred on the bounding-box centre of the source
// file; `offset` (double) restores the source coordinates on export. That is
// what lets a UTM-sized model (678000, 5403500) keep sub-millimetre precision.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace perclod {

// pi, once for every module.
constexpr double kPi = 3.14159265358979323846;

struct Material {
  std::string name;
  std::array<float, 3> color{0.8f, 0.8f, 0.8f};  // linear-ish diffuse, 0..1
  bool has_color = false;                          // false: the file gave none
};

// The contract (checked by validate() below; every module's entry points call
// it, so none keeps its own checks):
//  * positions holds 3 finite floats per vertex, indices 3 per triangle, and
//    every index is below vertex_count();
//  * component and material are each either empty or hold one id per
//    triangle. Empty component: the whole scene is one component, id 0.
//    Empty material: every triangle has the default material (no colour of
//    its own, so it is drawn in its component's colour);
//  * a non-empty component array indexes component_names (every id below its
//    size); a non-empty material array likewise indexes materials.
// Read the per-triangle ids through component_of() and material_of(), which
// apply the rule for empty arrays.
struct Scene {
  std::vector<float> positions;         // x,y,z per vertex (recentred)
  std::vector<uint32_t> indices;        // 3 per triangle
  std::vector<uint32_t> component;      // per triangle: index into component_names (or empty)
  std::vector<uint32_t> material;       // per triangle: index into materials (or empty)
  std::vector<std::string> component_names;
  std::vector<Material> materials;
  std::array<double, 3> offset{0, 0, 0};  // source = position + offset

  size_t vertex_count() const { return positions.size() / 3; }
  size_t triangle_count() const { return indices.size() / 3; }
  size_t component_count() const { return component_names.size(); }
  uint32_t component_of(size_t triangle) const { return component.empty() ? 0 : component[triangle]; }
  // The triangle's material, or nullptr for the default one.
  const Material* material_of(size_t triangle) const {
    return material.empty() ? nullptr : &materials[material[triangle]];
  }
};

// Throws std::invalid_argument("scene: ...") naming the first broken rule of
// the contract above (and the triangle or vertex that breaks it).
inline void validate(const Scene& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("scene: " + what); };
  auto str = [](size_t n) { return std::to_string(n); };
  if (s.positions.size() % 3) fail("positions size " + str(s.positions.size()) + " is not a multiple of 3");
  if (s.indices.size() % 3) fail("indices size " + str(s.indices.size()) + " is not a multiple of 3");
  const size_t nv = s.vertex_count(), nt = s.triangle_count();
  for (size_t i = 0; i < s.indices.size(); ++i)
    if (s.indices[i] >= nv)
      fail("triangle " + str(i / 3) + " uses vertex " + str(s.indices[i]) + " but there are only " + str(nv) +
           " vertices");
  for (size_t i = 0; i < s.positions.size(); ++i)
    if (!std::isfinite(s.positions[i])) fail("vertex " + str(i / 3) + " is not finite (a NaN or infinite coordinate)");
  auto check_ids = [&](const std::vector<uint32_t>& ids, size_t names, const char* what, const char* table) {
    if (ids.empty()) return;
    if (ids.size() != nt) fail(str(ids.size()) + " " + what + " ids for " + str(nt) + " triangles");
    for (size_t t = 0; t < nt; ++t)
      if (ids[t] >= names)
        fail("triangle " + str(t) + " has " + what + " " + str(ids[t]) + " but there are only " + str(names) + " " +
             table);
  };
  check_ids(s.component, s.component_names.size(), "component", "component names");
  check_ids(s.material, s.materials.size(), "material", "materials");
}

// Per-triangle perceptual label (docs/method.md section 4). Values are stable:
// they are written to label files.
enum class Label : uint8_t {
  Perceptible = 0,
  Imperceptible = 1,
  Undisplayable = 2,
};

// Axis-aligned box over the scene's positions (recentred coordinates).
// An axis-aligned box. Default: the point box at the origin; empty(): the
// box nothing is in yet (lo +inf, hi -inf), which grow() widens to each point.
struct Bounds {
  std::array<float, 3> lo{0, 0, 0}, hi{0, 0, 0};
  static Bounds empty() {
    Bounds b;
    b.lo = {INFINITY, INFINITY, INFINITY};
    b.hi = {-INFINITY, -INFINITY, -INFINITY};
    return b;
  }
  bool is_empty() const { return !(lo[0] <= hi[0]); }
  void grow(const float* p) {
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  }
  std::array<float, 3> center() const {
    return {(lo[0] + hi[0]) * 0.5f, (lo[1] + hi[1]) * 0.5f, (lo[2] + hi[2]) * 0.5f};
  }
  float diagonal() const {
    float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
  }
};

// Some triangles of `s` (`triangles`, indices into s) as a scene of their
// own, on their own vertices, with their components and materials (the same
// names and materials, so component ids keep their meaning). `vertex`: s's
// vertex -> the subset's, all UINT32_MAX on entry and again on return (kept
// by a caller taking many subsets, so each does not fill one the size of s).
inline Scene subset_scene(const Scene& s, const std::vector<uint32_t>& triangles, std::vector<uint32_t>& vertex) {
  Scene out;
  out.component_names = s.component_names;
  out.materials = s.materials;
  out.offset = s.offset;
  vertex.resize(s.vertex_count(), UINT32_MAX);
  for (const uint32_t t : triangles) {
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = s.indices[3 * size_t(t) + c];
      if (vertex[v] == UINT32_MAX) {
        vertex[v] = uint32_t(out.positions.size() / 3);
        out.positions.insert(out.positions.end(), &s.positions[3 * size_t(v)], &s.positions[3 * size_t(v)] + 3);
      }
      out.indices.push_back(vertex[v]);
    }
    if (!s.component.empty()) out.component.push_back(s.component[t]);
    if (!s.material.empty()) out.material.push_back(s.material[t]);
  }
  for (const uint32_t t : triangles)
    for (int c = 0; c < 3; ++c) vertex[s.indices[3 * size_t(t) + c]] = UINT32_MAX;
  return out;
}

// Bounds of the vertices referenced by triangles (unreferenced ones ignored).
inline Bounds scene_bounds(const Scene& s) {
  if (s.indices.empty()) return Bounds{};
  Bounds b = Bounds::empty();
  for (uint32_t i : s.indices) b.grow(&s.positions[3 * size_t(i)]);
  return b;
}

}  // namespace perclod
