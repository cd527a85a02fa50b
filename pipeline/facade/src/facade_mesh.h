// facade_mesh.h - the few solids the facade is made of, and their exact
// triangle counts. Private to perclod_facade.
//
// Parts are described in a wall's local frame: u along the wall, w into the
// building (w = 0 is the wall's outer face, w < 0 stands in front of it),
// z up. A WallFrame maps that frame to the building's frame by a rotation
// about z and a translation, so orientation (counter-clockwise seen from
// outside) survives the mapping.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace perclod::facade_detail {

using Vec3 = std::array<double, 3>;

// Triangles of each primitive; the generator's closed-form count is built
// from these and checked against the generated scene by the tests.
constexpr size_t kBoxTriangles = 12;
constexpr size_t kQuadTriangles = 2;
// A closed surface of revolution: `rings` profile rings of `segments`
// vertices, side quads between consecutive rings, a fan cap at each end.
constexpr size_t lathe_triangles(size_t rings, size_t segments) {
  return 2 * segments * (rings - 1) + 2 * segments;
}

struct WallFrame {
  Vec3 origin{0, 0, 0};  // building coordinates of local (0, 0, 0)
  double du_x = 1, du_y = 0;  // unit direction of u in the xy plane; w is z x u
  Vec3 to_building(double u, double w, double z) const {
    // w direction = (-du_y, du_x): the left turn of u, pointing inwards.
    return {origin[0] + u * du_x - w * du_y, origin[1] + u * du_y + w * du_x, origin[2] + z};
  }
};

// An axis-aligned box in a wall's local frame.
struct LocalBox {
  double u0, u1, w0, w1, z0, z1;
};

// Accumulates the building in double precision, one component at a time.
class MeshBuilder {
 public:
  void reserve(size_t triangles);
  // Starts a new component; following parts belong to it until the next call.
  void begin_component(std::string name);
  void set_material(uint32_t material) { material_ = material; }

  void box(const WallFrame& f, const LocalBox& b);
  // Quad in the plane w = const, spanning [u0,u1] x [z0,z1], facing -w (outwards).
  void outward_quad(const WallFrame& f, double w, double u0, double u1, double z0, double z1);
  // Surface of revolution about the vertical axis (u, w): radii[i] at heights[i]
  // (increasing), `segments` around, closed by fan caps.
  void lathe(const WallFrame& f, double u, double w, const std::vector<double>& heights,
             const std::vector<double>& radii, int segments);

  size_t triangle_count() const { return indices_.size() / 3; }
  size_t vertex_count() const { return positions_.size(); }

  // Hands the mesh over: positions recentred on the bounding-box centre (the
  // centre is returned in `offset`), names moved out.
  void finish(std::vector<float>& positions, std::vector<uint32_t>& indices,
              std::vector<uint32_t>& component, std::vector<uint32_t>& material,
              std::vector<std::string>& component_names, std::array<double, 3>& offset);

 private:
  uint32_t vertex(const Vec3& p);
  void triangle(uint32_t a, uint32_t b, uint32_t c);

  std::vector<Vec3> positions_;
  std::vector<uint32_t> indices_, component_, material_ids_;
  std::vector<std::string> names_;
  uint32_t material_ = 0;
};

}  // namespace perclod::facade_detail
