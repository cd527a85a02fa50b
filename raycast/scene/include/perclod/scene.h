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
#include <string>
#include <vector>

namespace perclod {

struct Material {
  std::string name;
  std::array<float, 3> color{0.8f, 0.8f, 0.8f};  // linear-ish diffuse, 0..1
  bool has_color = false;                          // false: the file gave none
};

struct Scene {
  std::vector<float> positions;         // x,y,z per vertex (recentred)
  std::vector<uint32_t> indices;        // 3 per triangle
  std::vector<uint32_t> component;      // per triangle: index into component_names
  std::vector<uint32_t> material;       // per triangle: index into materials
  std::vector<std::string> component_names;
  std::vector<Material> materials;
  std::array<double, 3> offset{0, 0, 0};  // source = position + offset

  size_t vertex_count() const { return positions.size() / 3; }
  size_t triangle_count() const { return indices.size() / 3; }
  size_t component_count() const { return component_names.size(); }
};

// Per-triangle perceptual label (method.md section 4). Values are stable:
// they are written to label files.
enum class Label : uint8_t {
  Perceptible = 0,
  Imperceptible = 1,
  Undisplayable = 2,
};

inline const char* label_name(Label l) {
  switch (l) {
    case Label::Perceptible: return "perceptible";
    case Label::Imperceptible: return "imperceptible";
    case Label::Undisplayable: return "undisplayable";
  }
  return "?";
}

// Axis-aligned box over the scene's positions (recentred coordinates).
struct Bounds {
  std::array<float, 3> lo{0, 0, 0}, hi{0, 0, 0};
  std::array<float, 3> center() const {
    return {(lo[0] + hi[0]) * 0.5f, (lo[1] + hi[1]) * 0.5f, (lo[2] + hi[2]) * 0.5f};
  }
  float diagonal() const {
    float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
  }
};

// Bounds of the vertices referenced by triangles (unreferenced ones ignored).
inline Bounds scene_bounds(const Scene& s) {
  Bounds b;
  if (s.indices.empty()) return b;
  b.lo = {INFINITY, INFINITY, INFINITY};
  b.hi = {-INFINITY, -INFINITY, -INFINITY};
  for (uint32_t i : s.indices)
    for (int a = 0; a < 3; ++a) {
      float v = s.positions[3 * size_t(i) + a];
      b.lo[a] = std::min(b.lo[a], v);
      b.hi[a] = std::max(b.hi[a], v);
    }
  return b;
}

}  // namespace perclod
