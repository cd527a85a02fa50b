// perclod/facade.h - a parametric building facade, the project's known-answer
// and scale fixture.
//
// The generator builds a box-shaped building whose decorated walls carry a
// grid of floors x bays windows with frames, mullions, transoms and sills,
// a cornice segment per bay and floor, round columns with capitals between
// the bays, and a parapet of balusters on the roof edge. Switches add hidden
// interior parts, coplanar overlapping panels and sub-pixel ornaments: the
// cases the perception, ray-casting and simplification modules must handle.
//
// Geometry (before recentring): Z up, metres. Wall 0, the main facade, has
// its outer face in the plane y = 0 and faces -y; it runs along +x from the
// corner (0, 0). The footprint is W x depth with W = bays * bay_width for
// sides = 1 (walls 1..3 are plain slabs), and W x W for sides = 4 (every wall
// is a copy of wall 0 turned about the building's centre, `depth` unused).
// Walls of thickness 0.3 m meet corner to corner like a pinwheel, so no two
// solids overlap; roof, foundation and glass seal the inside, so interior
// parts cannot be seen from any viewpoint outside. The scene is recentred on
// its bounding-box centre, which is stored in Scene::offset.
//
// Every part is its own component, named
//   [sideS_]floorF_bayB_<part>   part: wall_left, wall_right, wall_below,
//                                wall_above, glass, frame, mullionM, transomT,
//                                sill, cornice, ornaments, plaque_a, plaque_b
//   [sideS_]floorF_colC_column / _capital   (C = 1..bays-1, between bays)
//   [sideS_]bayB_parapet, [sideS_]bayB_balusterJ
//   wall_side1..3 (sides = 1 only), roof, foundation, interior_floorF_slab,
//   interior_floorF_partitionC
// (the sideS_ prefix only when sides = 4). Materials, always all present in
// this order: wall, frame, glass, stone, roof, interior, ornament, plaque_a,
// plaque_b. Solid parts are closed, outward-oriented (counter-clockwise seen
// from outside) meshes; glass and plaques are single quads facing outwards.
// Vertices are shared only within a component. No degenerate triangles. The
// output depends on the parameters only (no randomness).
#pragma once

#include <cstddef>
#include <cstdint>

#include "perclod/scene.h"

namespace perclod {

struct FacadeParams {
  int floors = 4, bays = 6;  // window grid of each decorated wall
  double floor_height = 3.5, bay_width = 3.0, depth = 12.0;  // metres
  int sides = 1;  // 1: one facade (facing -y) on a plain box; 4: all four walls decorated
  bool frames = true, mullions = true, sills = true, cornices = true, columns = true,
       balusters = true;
  int mullions_per_window = 1, transoms_per_window = 1;  // used when `mullions`
  int column_segments = 12;    // tessellation of columns and capitals (main knob for count)
  int balusters_per_bay = 6;   // used when `balusters`
  int baluster_segments = 8;   // tessellation of one baluster
  bool hidden_interior = false;     // floor slabs and partitions, never visible from outside
  bool coplanar_panels = false;     // two overlapping plaques lying in the wall's face plane
  bool subpixel_ornaments = false;  // 1.5 cm studs above each window: sub-pixel at 56 m+
  int ornament_detail = 0;  // extra rings on every turned part (column entasis, baluster
                            // profile, capital): scales the count up to 2M and beyond
  uint64_t seed = 1;        // reserved: the generator uses no randomness today
};

// Throws std::invalid_argument naming the offending field when the
// parameters cannot make a valid building (counts < 1, sides not 1 or 4,
// segments < 3, sizes too small for the window layout, > 2^32 vertices...).
void check_facade_params(const FacadeParams& p);

// Builds the building. Throws like check_facade_params.
Scene generate_facade(const FacadeParams& p);

// Exact triangle count of generate_facade(p), computed from the parameters
// alone (closed form, nothing generated). Throws like check_facade_params.
size_t facade_triangle_count(const FacadeParams& p);

// Parameters (defaults where possible) whose triangle count is within about
// 10% of `target`, for targets from 1,000 to several million. Throws
// std::invalid_argument when target is below what the smallest building has.
FacadeParams facade_params_for_triangles(size_t target);

}  // namespace perclod
