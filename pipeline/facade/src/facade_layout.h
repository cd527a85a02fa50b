// facade_layout.h - where every part of the facade goes, derived from the
// parameters. Private to perclod_facade; shared by the generator and the
// parameter check so both agree on what fits.
#pragma once

#include <algorithm>
#include <cstddef>

#include "perclod/facade.h"

namespace perclod::facade_detail {

// Fixed sizes (metres). Everything else scales with floor height or bay width.
constexpr double kWallThickness = 0.3;
constexpr double kRoofThickness = 0.2;
constexpr double kFrameWidth = 0.06, kFrameHalfDepth = 0.04;
constexpr double kBarHalfWidth = 0.025, kBarHalfDepth = 0.03;  // mullions, transoms
constexpr double kGlassOverlap = 0.02;   // glass reaches into the frame/jambs: no cracks
constexpr double kSillOverhang = 0.08, kSillHeight = 0.06, kSillDepth = 0.1;
constexpr double kColumnGap = 0.05;      // between a column's widest part and the wall
constexpr double kOrnamentSize = 0.015;  // sub-pixel studs (one pixel is 3.3 cm at 56 m)
constexpr int kOrnamentsPerWindow = 6;
constexpr double kInteriorGap = 0.01;    // interior parts keep clear of the walls
constexpr double kSlabThickness = 0.2, kPartitionHalfWidth = 0.05;
constexpr double kPlinthHeight = 0.15, kRailHeight = 0.1, kBalusterHeight = 0.7;
constexpr double kParapetInset = 0.02;

// One window cell (floor f, bay k) in a wall's local frame (see facade_mesh.h).
struct WindowCell {
  double u0, u1;  // the cell's wall span (the last bay stops short of the next wall)
  double z0, z1;  // floor bottom and top
  double x0, x1;  // window opening along u
  double s0, s1;  // window opening along z (sill line, head)
};

struct Layout {
  double bw, fh, t;           // bay width, floor height, wall thickness
  double wall_length;         // outer length of a decorated wall (bays * bw)
  double footprint_x, footprint_y;
  double window_width, window_height, sill_rise;
  double cornice_height, cornice_depth;
  double column_radius, column_axis_w, capital_height, base_height;
  double glass_w;             // glass plane depth inside the wall

  explicit Layout(const FacadeParams& p)
      : bw(p.bay_width), fh(p.floor_height), t(kWallThickness) {
    wall_length = p.bays * bw;
    footprint_x = wall_length;
    footprint_y = p.sides == 4 ? wall_length : p.depth;
    window_width = 0.45 * bw;
    window_height = 0.45 * fh;
    sill_rise = 0.27 * fh;
    cornice_height = 0.09 * fh;
    column_radius = std::min(0.06 * bw, 0.05 * fh);
    column_axis_w = -(kColumnGap + 1.5 * column_radius);
    cornice_depth = 2 * kColumnGap + 3 * column_radius;
    capital_height = 0.08 * fh;
    base_height = 0.04 * fh;
    glass_w = 0.5 * t;
  }

  double height(const FacadeParams& p) const { return p.floors * fh; }

  WindowCell cell(int floor, int bay, int bays) const {
    WindowCell c;
    c.u0 = bay * bw;
    c.u1 = bay + 1 == bays ? wall_length - t : (bay + 1) * bw;
    c.z0 = floor * fh;
    c.z1 = c.z0 + fh;
    c.x0 = bay * bw + 0.5 * (bw - window_width);
    c.x1 = c.x0 + window_width;
    c.s0 = c.z0 + sill_rise;
    c.s1 = c.s0 + window_height;
    return c;
  }
};

// Ring counts of the turned parts (ornament_detail adds rings) and the
// closed-form triangle count (facade_count.cpp), unchecked.
size_t shaft_rings(const FacadeParams& p);
size_t capital_rings(const FacadeParams& p);
size_t baluster_rings(const FacadeParams& p);
size_t building_triangles(const FacadeParams& p);

}  // namespace perclod::facade_detail
