// The model readers' shared parts (private to perclod_io): the file as read
// before recentring, errors that name the file, and polygon triangulation.
// Each format's reader is a file of its own; load.cpp picks one and builds
// the Scene (build_scene recentres in double, then converts to float).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "perclod/load.h"

namespace perclod::detail {

// The file as read, before recentring: double positions, polygons already triangulated.
struct RawModel {
  std::vector<double> positions;  // xyz
  std::vector<uint32_t> indices;
  std::vector<uint32_t> component, material;
  std::vector<std::string> component_names;
  std::vector<Material> materials;
  // Components are the file's objects even when there is only one (CityJSON:
  // one per CityObject); else a file with at most one group gets connected parts.
  bool objects_are_components = false;
};

[[noreturn]] void fail(const std::string& path, const std::string& what, size_t line = 0);
// A number and nothing after it (a leading '+' allowed), as OBJ and CityJSON
// LOD names write them.
bool parse_double(std::string_view w, double& v);
// The whole file; fails naming it when it is missing, a folder or unreadable.
std::string read_file(const std::string& path);

// Triangulates polygon `poly` (indices into pos) by ear clipping in the plane
// of its Newell normal (or of `normal`, when given: a ring with holes bridged
// in is clipped in its outer ring's plane); falls back to a fan if the polygon
// is self-intersecting (or too costly to clip); returns whether that fallback
// fanned over 3 corners.
bool triangulate(const std::vector<double>& pos, const std::vector<uint32_t>& poly, std::vector<uint32_t>& out,
                 const std::array<double, 3>* normal = nullptr);
// Triangulates a polygon with holes (rings of indices into pos, the first the
// outer one; every ring at least 3 corners): holes are turned against the
// outer ring, bridged into it from right to left and the one ring is ear
// clipped in the outer ring's plane. Counts the polygon in
// polygons_holes_failed when its triangles do not cover exactly the outer
// area minus the holes' (a hole outside its ring or overlapping another,
// self-intersecting rings), and in polygons_fanned as triangulate() does.
void triangulate_with_holes(const std::vector<double>& pos, std::vector<std::vector<uint32_t>> rings,
                            std::vector<uint32_t>& out, LoadReport& rep);

// OBJ (obj_reader.cpp): perclod's own reader, in double precision.
RawModel read_obj(const std::string& path, LoadReport& rep);
// A file without an extension is read as OBJ if its first statements are OBJ
// statements and one is a vertex.
bool looks_like_obj(const std::string& path);

// CityJSON 1.0-2.0 (cityjson_reader.cpp).
RawModel read_cityjson(const std::string& path, const LoadOptions& opt, LoadReport& rep);
// A file without an extension (and not OBJ) is CityJSON when it is a JSON
// object whose "type" is "CityJSON".
bool looks_like_cityjson(const std::string& path);

// Every other format, through assimp (assimp_reader.cpp), after the checks
// that keep assimp from hanging on hostile PLY and GLB files.
RawModel read_assimp(const std::string& path, LoadReport& rep);

}  // namespace perclod::detail
