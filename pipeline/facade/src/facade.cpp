// facade.cpp - builds the parametric building, part by part.
//
// Order of construction: for each decorated wall, every window cell (wall
// panels, glass, frame, bars, sill, cornice, ornaments, plaques), then the
// columns of each floor, then the roof parapet; after the walls, the plain
// walls (sides = 1), the roof slab, the foundation and the hidden interior. Each part is a
// component of its own; see perclod/facade.h for the names.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "facade_layout.h"
#include "facade_mesh.h"
#include "perclod/facade.h"

namespace perclod {
namespace facade_detail {
namespace {

enum MaterialId : uint32_t { kWall, kFrame, kGlass, kStone, kRoof, kInterior, kOrnament, kPlaqueA, kPlaqueB };

std::vector<Material> facade_materials() {
  auto m = [](const char* name, float r, float g, float b) {
    return Material{name, {r, g, b}, true};
  };
  return {m("wall", 0.85f, 0.78f, 0.65f),  m("frame", 0.93f, 0.93f, 0.90f),
          m("glass", 0.20f, 0.32f, 0.45f), m("stone", 0.70f, 0.70f, 0.68f),
          m("roof", 0.45f, 0.25f, 0.20f),  m("interior", 0.50f, 0.50f, 0.50f),
          m("ornament", 0.80f, 0.65f, 0.20f), m("plaque_a", 0.75f, 0.20f, 0.20f),
          m("plaque_b", 0.20f, 0.60f, 0.30f)};
}

// Heights of `rings` evenly spaced profile rings from z0 to z1.
std::vector<double> ring_heights(size_t rings, double z0, double z1) {
  std::vector<double> h(rings);
  for (size_t i = 0; i < rings; ++i) h[i] = z0 + (z1 - z0) * double(i) / double(rings - 1);
  return h;
}

// Radii following `shape` (of t in 0..1) at each ring.
template <class Shape>
std::vector<double> ring_radii(size_t rings, Shape shape) {
  std::vector<double> r(rings);
  for (size_t i = 0; i < rings; ++i) r[i] = shape(double(i) / double(rings - 1));
  return r;
}

class FacadeBuilder {
 public:
  explicit FacadeBuilder(const FacadeParams& p) : p_(p), l_(p) {}

  Scene build() {
    mesh_.reserve(building_triangles(p_));
    for (int side = 0; side < p_.sides; ++side) decorated_wall(side);
    if (p_.sides == 1)
      for (int side = 1; side < 4; ++side) plain_wall(side);
    roof();
    foundation();
    if (p_.hidden_interior) interior();
    Scene s;
    mesh_.finish(s.positions, s.indices, s.component, s.material, s.component_names, s.offset);
    s.materials = facade_materials();
    return s;
  }

 private:
  // Wall `side` starts at corner `side` of the footprint and runs
  // counter-clockwise (seen from above); its outward normal is -w.
  WallFrame wall_frame(int side) const {
    const double X = l_.footprint_x, Y = l_.footprint_y;
    static constexpr double kDir[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    const double origin[4][2] = {{0, 0}, {X, 0}, {X, Y}, {0, Y}};
    WallFrame f;
    f.origin = {origin[side][0], origin[side][1], 0};
    f.du_x = kDir[side][0];
    f.du_y = kDir[side][1];
    return f;
  }
  double wall_length(int side) const { return side % 2 == 0 ? l_.footprint_x : l_.footprint_y; }

  void part(const std::string& name, MaterialId m) {
    mesh_.begin_component(prefix_ + name);
    mesh_.set_material(m);
  }
  static std::string cell_name(int floor, int bay, const char* what) {
    return "floor" + std::to_string(floor) + "_bay" + std::to_string(bay) + "_" + what;
  }

  void decorated_wall(int side) {
    prefix_ = p_.sides == 4 ? "side" + std::to_string(side) + "_" : "";
    const WallFrame f = wall_frame(side);
    for (int floor = 0; floor < p_.floors; ++floor)
      for (int bay = 0; bay < p_.bays; ++bay) window_cell(f, floor, bay);
    if (p_.columns)
      for (int floor = 0; floor < p_.floors; ++floor)
        for (int c = 1; c < p_.bays; ++c) column(f, floor, c);
    if (p_.balusters)
      for (int bay = 0; bay < p_.bays; ++bay) parapet(f, bay);
    prefix_.clear();
  }

  void window_cell(const WallFrame& f, int floor, int bay) {
    const WindowCell c = l_.cell(floor, bay, p_.bays);
    const double t = l_.t;
    // The wall around the opening: four panels through the wall's thickness.
    part(cell_name(floor, bay, "wall_left"), kWall);
    mesh_.box(f, {c.u0, c.x0, 0, t, c.z0, c.z1});
    part(cell_name(floor, bay, "wall_right"), kWall);
    mesh_.box(f, {c.x1, c.u1, 0, t, c.z0, c.z1});
    part(cell_name(floor, bay, "wall_below"), kWall);
    mesh_.box(f, {c.x0, c.x1, 0, t, c.z0, c.s0});
    part(cell_name(floor, bay, "wall_above"), kWall);
    mesh_.box(f, {c.x0, c.x1, 0, t, c.s1, c.z1});
    // Glass recessed to mid-wall, reaching a little into the jambs so no ray
    // slips between pane and wall.
    part(cell_name(floor, bay, "glass"), kGlass);
    mesh_.outward_quad(f, l_.glass_w, c.x0 - kGlassOverlap, c.x1 + kGlassOverlap,
                       c.s0 - kGlassOverlap, c.s1 + kGlassOverlap);
    if (p_.frames) frame(f, c, floor, bay);
    if (p_.mullions) bars(f, c, floor, bay);
    if (p_.sills) {
      part(cell_name(floor, bay, "sill"), kStone);
      mesh_.box(f, {c.x0 - kSillOverhang, c.x1 + kSillOverhang, -kSillDepth, 0,
                    c.s0 - kSillHeight, c.s0});
    }
    if (p_.cornices) cornice(f, c, floor, bay);
    if (p_.subpixel_ornaments) ornaments(f, c, floor, bay);
    if (p_.coplanar_panels) plaques(f, c, floor, bay);
  }

  // Four members lining the opening around the glass plane.
  void frame(const WallFrame& f, const WindowCell& c, int floor, int bay) {
    part(cell_name(floor, bay, "frame"), kFrame);
    const double w0 = l_.glass_w - kFrameHalfDepth, w1 = l_.glass_w + kFrameHalfDepth;
    const double fw = kFrameWidth;
    mesh_.box(f, {c.x0, c.x0 + fw, w0, w1, c.s0, c.s1});
    mesh_.box(f, {c.x1 - fw, c.x1, w0, w1, c.s0, c.s1});
    mesh_.box(f, {c.x0 + fw, c.x1 - fw, w0, w1, c.s0, c.s0 + fw});
    mesh_.box(f, {c.x0 + fw, c.x1 - fw, w0, w1, c.s1 - fw, c.s1});
  }

  // Vertical mullions across the glass; horizontal transoms cut into
  // segments between them, so no two bars overlap.
  void bars(const WallFrame& f, const WindowCell& c, int floor, int bay) {
    const double inset = p_.frames ? kFrameWidth : 0.0;
    const double a = c.x0 + inset, b = c.x1 - inset, lo = c.s0 + inset, hi = c.s1 - inset;
    const double w0 = l_.glass_w - kBarHalfDepth, w1 = l_.glass_w + kBarHalfDepth;
    const double h = kBarHalfWidth;
    const int m = p_.mullions_per_window, n = p_.transoms_per_window;
    auto mullion_u = [&](int j) { return a + (b - a) * j / (m + 1); };  // j = 1..m
    for (int j = 1; j <= m; ++j) {
      part(cell_name(floor, bay, "mullion") + std::to_string(j - 1), kFrame);
      mesh_.box(f, {mullion_u(j) - h, mullion_u(j) + h, w0, w1, lo, hi});
    }
    for (int i = 1; i <= n; ++i) {
      part(cell_name(floor, bay, "transom") + std::to_string(i - 1), kFrame);
      const double z = lo + (hi - lo) * i / (n + 1);
      for (int j = 0; j <= m; ++j) {
        double u0 = j == 0 ? a : mullion_u(j) + h;
        double u1 = j == m ? b : mullion_u(j + 1) - h;
        mesh_.box(f, {u0, u1, w0, w1, z - h, z + h});
      }
    }
  }

  // A stepped band at the top of the floor, in front of the wall, the whole
  // bay wide (it overhangs the columns below it).
  void cornice(const WallFrame& f, const WindowCell& c, int floor, int bay) {
    part(cell_name(floor, bay, "cornice"), kStone);
    const double u0 = bay * l_.bw, u1 = u0 + l_.bw, ch = l_.cornice_height, cd = l_.cornice_depth;
    mesh_.box(f, {u0, u1, -0.6 * cd, 0, c.z1 - ch, c.z1 - 0.5 * ch});
    mesh_.box(f, {u0, u1, -cd, 0, c.z1 - 0.5 * ch, c.z1});
  }

  // Studs of 1.5 cm on the panel above the window.
  void ornaments(const WallFrame& f, const WindowCell& c, int floor, int bay) {
    part(cell_name(floor, bay, "ornaments"), kOrnament);
    const double z = c.z0 + 0.75 * l_.fh, s = 0.5 * kOrnamentSize;
    for (int j = 0; j < kOrnamentsPerWindow; ++j) {
      double u = c.x0 + (c.x1 - c.x0) * (j + 0.5) / kOrnamentsPerWindow;
      mesh_.box(f, {u - s, u + s, -kOrnamentSize, 0, z - s, z + s});
    }
  }

  // Two plaques lying exactly in the wall's face plane (w = 0), overlapping
  // each other and the panel above the window: the tie-rule fixture.
  void plaques(const WallFrame& f, const WindowCell& c, int floor, int bay) {
    const double ww = c.x1 - c.x0, z0 = c.z0, fh = l_.fh;
    part(cell_name(floor, bay, "plaque_a"), kPlaqueA);
    mesh_.outward_quad(f, 0.0, c.x0, c.x0 + 0.6 * ww, z0 + 0.78 * fh, z0 + 0.86 * fh);
    part(cell_name(floor, bay, "plaque_b"), kPlaqueB);
    mesh_.outward_quad(f, 0.0, c.x0 + 0.4 * ww, c.x1, z0 + 0.80 * fh, z0 + 0.88 * fh);
  }

  // A round column between bays c-1 and c, standing clear of the wall:
  // square base, shaft with a slight entasis, flared capital under an abacus.
  void column(const WallFrame& f, int floor, int c) {
    const std::string name = "floor" + std::to_string(floor) + "_col" + std::to_string(c);
    const double u = c * l_.bw, w = l_.column_axis_w, r = l_.column_radius;
    const double z0 = floor * l_.fh, z_shaft = z0 + l_.base_height;
    const double z_top = z0 + l_.fh - l_.cornice_height;  // under the cornice
    const double z_capital = z_top - l_.capital_height, z_abacus = z_top - 0.4 * l_.capital_height;
    const int seg = p_.column_segments;

    part(name + "_column", kStone);
    mesh_.box(f, {u - 1.4 * r, u + 1.4 * r, w - 1.4 * r, w + 1.4 * r, z0, z_shaft});
    auto entasis = [r](double t) { return r * (1.0 - 0.12 * t + 0.03 * std::sin(std::numbers::pi * t)); };
    size_t rings = shaft_rings(p_);
    mesh_.lathe(f, u, w, ring_heights(rings, z_shaft, z_capital), ring_radii(rings, entasis), seg);

    part(name + "_capital", kStone);
    const double r_neck = entasis(1.0);
    auto echinus = [r, r_neck](double t) {
      return r_neck + (1.35 * r - r_neck) * std::sin(0.5 * std::numbers::pi * t);
    };
    rings = capital_rings(p_);
    mesh_.lathe(f, u, w, ring_heights(rings, z_capital, z_abacus), ring_radii(rings, echinus), seg);
    mesh_.box(f, {u - 1.5 * r, u + 1.5 * r, w - 1.5 * r, w + 1.5 * r, z_abacus, z_top});
  }

  // On the roof edge above the wall: plinth, balusters, hand rail. The last
  // bay stops where the next wall begins.
  void parapet(const WallFrame& f, int bay) {
    const double a = bay * l_.bw;
    const double b = bay + 1 == p_.bays ? l_.wall_length - l_.t : a + l_.bw;
    const double w0 = kParapetInset, w1 = l_.t - kParapetInset;
    const double z_plinth = l_.height(p_) + kRoofThickness, z_base = z_plinth + kPlinthHeight;
    const double z_rail = z_base + kBalusterHeight;
    const std::string name = "bay" + std::to_string(bay);
    part(name + "_parapet", kStone);
    mesh_.box(f, {a, b, w0, w1, z_plinth, z_base});
    mesh_.box(f, {a, b, w0, w1, z_rail, z_rail + kRailHeight});

    const int n = p_.balusters_per_bay;
    const double spacing = (b - a) / (n + 1);
    const double rb = std::min(0.45 * (0.5 * l_.t - kParapetInset), 0.35 * spacing);
    auto vase = [rb](double t) { return rb * (0.55 + 0.45 * std::sin(std::numbers::pi * t)); };
    const size_t rings = baluster_rings(p_);
    const auto heights = ring_heights(rings, z_base, z_rail);
    const auto radii = ring_radii(rings, vase);
    for (int j = 0; j < n; ++j) {
      part(name + "_baluster" + std::to_string(j), kStone);
      mesh_.lathe(f, a + spacing * (j + 1), 0.5 * l_.t, heights, radii, p_.baluster_segments);
    }
  }

  // sides = 1: the other three walls are plain slabs, pinwheel like the rest.
  void plain_wall(int side) {
    part("wall_side" + std::to_string(side), kWall);
    mesh_.box(wall_frame(side), {0, wall_length(side) - l_.t, 0, l_.t, 0, l_.height(p_)});
  }

  void roof() {
    part("roof", kRoof);
    const double z = l_.height(p_);
    mesh_.box(WallFrame{}, {0, l_.footprint_x, 0, l_.footprint_y, z, z + kRoofThickness});
  }

  // Under the walls: with the roof and the glass it seals the inside.
  void foundation() {
    part("foundation", kStone);
    mesh_.box(WallFrame{}, {0, l_.footprint_x, 0, l_.footprint_y, -kRoofThickness, 0});
  }

  // A floor slab per floor and a partition at every bay boundary, all
  // strictly inside the walls' inner faces: never visible from outside.
  void interior() {
    const double e = kInteriorGap, t = l_.t;
    const double x0 = t + e, x1 = l_.footprint_x - t - e, y0 = t + e, y1 = l_.footprint_y - t - e;
    const WallFrame world{};
    for (int floor = 0; floor < p_.floors; ++floor) {
      const double z0 = floor * l_.fh, z_slab = z0 + kSlabThickness;
      const std::string name = "interior_floor" + std::to_string(floor);
      part(name + "_slab", kInterior);
      mesh_.box(world, {x0, x1, y0, y1, z0 + e, z_slab});
      for (int c = 1; c < p_.bays; ++c) {
        part(name + "_partition" + std::to_string(c), kInterior);
        const double x = c * l_.bw;
        mesh_.box(world, {x - kPartitionHalfWidth, x + kPartitionHalfWidth, y0, y1, z_slab,
                          z0 + l_.fh - e});
      }
    }
  }

  const FacadeParams& p_;
  const Layout l_;
  MeshBuilder mesh_;
  std::string prefix_;
};

}  // namespace
}  // namespace facade_detail

Scene generate_facade(const FacadeParams& p) {
  check_facade_params(p);
  return facade_detail::FacadeBuilder(p).build();
}

}  // namespace perclod
