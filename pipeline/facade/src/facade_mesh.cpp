// facade_mesh.cpp - boxes, quads and turned parts for the facade generator.
#include "facade_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace perclod::facade_detail {

void MeshBuilder::reserve(size_t triangles) {
  indices_.reserve(3 * triangles);
  component_.reserve(triangles);
  material_ids_.reserve(triangles);
  positions_.reserve(triangles);  // about one vertex per triangle on average
}

void MeshBuilder::begin_component(std::string name) { names_.push_back(std::move(name)); }

uint32_t MeshBuilder::vertex(const Vec3& p) {
  positions_.push_back(p);
  return uint32_t(positions_.size() - 1);
}

void MeshBuilder::triangle(uint32_t a, uint32_t b, uint32_t c) {
  indices_.insert(indices_.end(), {a, b, c});
  component_.push_back(uint32_t(names_.size() - 1));
  material_ids_.push_back(material_);
}

void MeshBuilder::box(const WallFrame& f, const LocalBox& b) {
  // Corner i has u = bit 0, w = bit 1, z = bit 2.
  uint32_t v[8];
  for (int i = 0; i < 8; ++i)
    v[i] = vertex(f.to_building(i & 1 ? b.u1 : b.u0, i & 2 ? b.w1 : b.w0, i & 4 ? b.z1 : b.z0));
  // Each face counter-clockwise seen from outside (u, w, z is right-handed).
  static constexpr int kFaces[6][4] = {
      {0, 4, 6, 2},  // u0, normal -u
      {1, 3, 7, 5},  // u1, normal +u
      {0, 1, 5, 4},  // w0, normal -w (the outward face of a wall part)
      {2, 6, 7, 3},  // w1, normal +w
      {0, 2, 3, 1},  // z0, normal -z
      {4, 5, 7, 6},  // z1, normal +z
  };
  for (const auto& q : kFaces) {
    triangle(v[q[0]], v[q[1]], v[q[2]]);
    triangle(v[q[0]], v[q[2]], v[q[3]]);
  }
}

void MeshBuilder::outward_quad(const WallFrame& f, double w, double u0, double u1, double z0,
                               double z1) {
  uint32_t a = vertex(f.to_building(u0, w, z0)), b = vertex(f.to_building(u1, w, z0)),
           c = vertex(f.to_building(u1, w, z1)), d = vertex(f.to_building(u0, w, z1));
  triangle(a, b, c);
  triangle(a, c, d);
}

void MeshBuilder::lathe(const WallFrame& f, double u, double w, const std::vector<double>& heights,
                        const std::vector<double>& radii, int segments) {
  const size_t rings = heights.size();
  const uint32_t first = uint32_t(positions_.size());
  for (size_t i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      double a = 2.0 * std::numbers::pi * j / segments;
      vertex(f.to_building(u + radii[i] * std::cos(a), w + radii[i] * std::sin(a), heights[i]));
    }
  auto ring = [&](size_t i, int j) { return first + uint32_t(i * segments + j % segments); };
  // Angle grows counter-clockwise about +z, so (along the ring, up) faces outwards.
  for (size_t i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      triangle(ring(i, j), ring(i, j + 1), ring(i + 1, j + 1));
      triangle(ring(i, j), ring(i + 1, j + 1), ring(i + 1, j));
    }
  uint32_t bottom = vertex(f.to_building(u, w, heights.front()));
  uint32_t top = vertex(f.to_building(u, w, heights.back()));
  for (int j = 0; j < segments; ++j) {
    triangle(bottom, ring(0, j + 1), ring(0, j));
    triangle(top, ring(rings - 1, j), ring(rings - 1, j + 1));
  }
}

void MeshBuilder::finish(std::vector<float>& positions, std::vector<uint32_t>& indices,
                         std::vector<uint32_t>& component, std::vector<uint32_t>& material,
                         std::vector<std::string>& component_names,
                         std::array<double, 3>& offset) {
  Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max()};
  Vec3 hi{-lo[0], -lo[1], -lo[2]};
  for (const Vec3& p : positions_)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  for (int a = 0; a < 3; ++a) offset[a] = 0.5 * (lo[a] + hi[a]);
  positions.resize(3 * positions_.size());
  for (size_t i = 0; i < positions_.size(); ++i)
    for (int a = 0; a < 3; ++a) positions[3 * i + a] = float(positions_[i][a] - offset[a]);
  indices = std::move(indices_);
  component = std::move(component_);
  material = std::move(material_ids_);
  component_names = std::move(names_);
  positions_.clear();
}

}  // namespace perclod::facade_detail
