// facade_count.cpp - the facade's triangle count in closed form, and the
// parameter check. The generator emits exactly these parts; the tests hold
// generate_facade(p).triangle_count() == facade_triangle_count(p).
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "facade_layout.h"
#include "facade_mesh.h"
#include "perclod/facade.h"

namespace perclod {
namespace facade_detail {

// Ring counts of the turned parts; ornament_detail adds rings to each.
size_t shaft_rings(const FacadeParams& p) { return 2 + size_t(p.ornament_detail); }
size_t capital_rings(const FacadeParams& p) { return 3 + size_t(p.ornament_detail); }
size_t baluster_rings(const FacadeParams& p) { return 6 + size_t(p.ornament_detail); }

// Parts of one window cell (floor f, bay b).
size_t cell_triangles(const FacadeParams& p) {
  size_t n = 4 * kBoxTriangles + kQuadTriangles;  // wall panels around the opening, glass
  if (p.frames) n += 4 * kBoxTriangles;
  if (p.mullions) {
    size_t m = size_t(p.mullions_per_window), t = size_t(p.transoms_per_window);
    n += (m + t * (m + 1)) * kBoxTriangles;  // transoms are cut into segments by the mullions
  }
  if (p.sills) n += kBoxTriangles;
  if (p.cornices) n += 2 * kBoxTriangles;  // stepped profile: two boxes
  if (p.subpixel_ornaments) n += kOrnamentsPerWindow * kBoxTriangles;
  if (p.coplanar_panels) n += 2 * kQuadTriangles;
  return n;
}

// One column (base box + shaft) and its capital (echinus + abacus box).
size_t column_triangles(const FacadeParams& p) {
  size_t s = size_t(p.column_segments);
  return kBoxTriangles + lathe_triangles(shaft_rings(p), s) + lathe_triangles(capital_rings(p), s) +
         kBoxTriangles;
}

size_t baluster_triangles(const FacadeParams& p) {
  return lathe_triangles(baluster_rings(p), size_t(p.baluster_segments));
}

size_t decorated_wall_triangles(const FacadeParams& p) {
  size_t floors = size_t(p.floors), bays = size_t(p.bays);
  size_t n = floors * bays * cell_triangles(p);
  if (p.columns) n += floors * (bays - 1) * column_triangles(p);
  if (p.balusters)
    n += bays * (2 * kBoxTriangles + size_t(p.balusters_per_bay) * baluster_triangles(p));
  return n;
}

size_t building_triangles(const FacadeParams& p) {
  size_t n = size_t(p.sides) * decorated_wall_triangles(p);
  if (p.sides == 1) n += 3 * kBoxTriangles;  // plain side and back walls
  n += 2 * kBoxTriangles;                      // roof slab and foundation
  if (p.hidden_interior) n += size_t(p.floors) * size_t(p.bays) * kBoxTriangles;  // slab + partitions
  return n;
}

namespace {

constexpr size_t kMaxTriangles = 1000000000;  // keeps vertex ids far inside uint32

[[noreturn]] void bad(const std::string& what) {
  throw std::invalid_argument("facade parameters: " + what);
}

void require(bool ok, const char* field, const std::string& rule, double got) {
  if (!ok) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", got);
    bad(std::string(field) + " " + rule + " (got " + buf + ")");
  }
}

}  // namespace
}  // namespace facade_detail

void check_facade_params(const FacadeParams& p) {
  using namespace facade_detail;
  require(p.floors >= 1 && p.floors <= 100000, "floors", "must be in 1..100000", p.floors);
  require(p.bays >= 1 && p.bays <= 100000, "bays", "must be in 1..100000", p.bays);
  require(p.sides == 1 || p.sides == 4, "sides", "must be 1 or 4", p.sides);
  require(std::isfinite(p.floor_height) && p.floor_height >= 2.0 && p.floor_height <= 100.0,
          "floor_height", "must be in 2..100 m", p.floor_height);
  require(std::isfinite(p.bay_width) && p.bay_width >= 1.5 && p.bay_width <= 100.0, "bay_width",
          "must be in 1.5..100 m", p.bay_width);
  if (p.sides == 1)
    require(std::isfinite(p.depth) && p.depth >= 2.0 && p.depth <= 10000.0, "depth",
            "must be in 2..10000 m", p.depth);
  require(p.column_segments >= 3 && p.column_segments <= 100000, "column_segments",
          "must be in 3..100000", p.column_segments);
  require(p.baluster_segments >= 3 && p.baluster_segments <= 100000, "baluster_segments",
          "must be in 3..100000", p.baluster_segments);
  require(p.ornament_detail >= 0 && p.ornament_detail <= 100000, "ornament_detail",
          "must be in 0..100000", p.ornament_detail);
  require(p.mullions_per_window >= 0, "mullions_per_window", "must be >= 0", p.mullions_per_window);
  require(p.transoms_per_window >= 0, "transoms_per_window", "must be >= 0", p.transoms_per_window);
  require(p.balusters_per_bay >= 1, "balusters_per_bay", "must be >= 1", p.balusters_per_bay);

  // The bars must leave glass between them (at least 2 cm per pane).
  Layout l(p);
  double frame = p.frames ? kFrameWidth : 0.0;
  double pane_w = (l.window_width - 2 * frame) / (p.mullions_per_window + 1) - 2 * kBarHalfWidth;
  double pane_h = (l.window_height - 2 * frame) / (p.transoms_per_window + 1) - 2 * kBarHalfWidth;
  if (p.mullions) {
    require(pane_w >= 0.02, "mullions_per_window", "too many for the window width",
            p.mullions_per_window);
    require(pane_h >= 0.02, "transoms_per_window", "too many for the window height",
            p.transoms_per_window);
  }
  // Balusters must be at least 1 cm thick in the shortest (last) bay.
  if (p.balusters)
    require(0.35 * (l.bw - l.t) / (p.balusters_per_bay + 1) >= 0.005, "balusters_per_bay",
            "too many for the bay width", p.balusters_per_bay);

  // Overflow-safe size guard: the count in double first.
  double approx = double(p.sides) * p.floors * p.bays *
                  (300.0 + 4.0 * (p.column_segments + p.baluster_segments) *
                               (4.0 + p.ornament_detail) * (1.0 + p.balusters_per_bay) +
                   12.0 * (p.mullions_per_window + 1.0) * (p.transoms_per_window + 1.0));
  if (approx > 4.0 * kMaxTriangles || building_triangles(p) > kMaxTriangles)
    bad("more than 1e9 triangles: reduce floors, bays, sides, segments or ornament_detail");
}

size_t facade_triangle_count(const FacadeParams& p) {
  check_facade_params(p);
  return facade_detail::building_triangles(p);
}

}  // namespace perclod
