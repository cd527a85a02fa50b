// perclod/load.h - model files into a Scene.
//
// OBJ is read by perclod's own parser in double precision (Debian's assimp is
// built with float, which loses centimetres at UTM coordinates): the bounding
// box is found in double, positions are recentred on its centre and only then
// become float; Scene::offset keeps the centre. PLY, glTF/GLB, STL, IFC, DAE,
// FBX go through assimp (float; recentred the same way).
//
// CityJSON (1.0, 1.1, 2.0): a `.city.json`, `.cityjson` or `.json` file (or
// one without an extension) whose top-level "type" is "CityJSON" - the content
// decides, a `.json` that is not CityJSON is a LoadError. Vertices go through
// the file's `transform` (v * scale + translate) in double, then are recentred
// like OBJ. One component per CityObject with geometry (even if only one
// has geometry: no connected parts): a top-level object is
// named by its id, a child (an object with "parents": BuildingPart,
// BuildingInstallation...) "<top-level id>/<child id>" (deeper descendants
// "<top>/<parent>/<child>"), and a top-level object whose descendants have
// geometry names its own geometry "<id>/<id>", so find_buildings() groups a
// building with its parts ('/' inside an id becomes '|'). Geometry:
// MultiSurface, CompositeSurface, Solid, MultiSolid, CompositeSolid and
// GeometryInstance (templates); surfaces are polygons with holes, joined into
// one ring by bridge edges and ear clipped. LoadOptions::cityjson_lod picks
// the LOD; MultiPoint/MultiLineString geometries are skipped and counted.
// Colours: the appearance's material diffuseColor where a surface has one
// (the "default-theme-material", else the first theme), else the semantic
// surface type (RoofSurface red, WallSurface light grey, GroundSurface dark,
// Window blue, Door brown...), else the default. The file's
// metadata.referenceSystem goes out in LoadReport::reference_system.
//
// Components: an OBJ's o/g groups, assimp's nodes/meshes (CityJSON: above); where one has at
// most one, the connected parts after welding equal positions.
// Nothing is silently dropped: polygons are triangulated, zero-area and
// repeated-vertex triangles are kept and counted. NaN/inf coordinates,
// out-of-range indices, unreadable or empty files throw LoadError naming the
// file (and line) and what is wrong.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <optional>
#include <stdexcept>
#include <string>

#include "perclod/scene.h"

namespace perclod {

// The largest model, metres across its bounding box after the unit scale:
// perclod renders, traces and judges in float, and its labels and LODs go
// wrong for models some thousand times larger (a cube 2e13 m across got an
// empty LOD, 2e11 m the right one). A larger model is refused naming the
// file and its size.
constexpr double kMaxModelSpan = 1e8;

struct LoadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct LoadOptions {
  double scale = 1.0;  // unit scale applied to source coordinates (e.g. 0.001 for mm)
  // CityJSON only: the LOD whose geometry is read. "" = the highest LOD each
  // CityObject has; else a LOD such as "2", "2.2", "3", compared as a number
  // ("2" matches "2.0", not "2.2"). A CityObject with geometry but none at
  // that LOD is skipped and counted (LoadReport::cityjson_objects_without_lod).
  std::string cityjson_lod = "";
  // Recentre on this point (source coordinates times the scale) instead of
  // the box's centre: a second file read into the first's frame (Scene::offset)
  // gets the float positions the first would give, rounded once.
  std::optional<std::array<double, 3>> centre = std::nullopt;
};

struct LoadReport {
  size_t polygons = 0;              // faces in the file
  size_t polygons_triangulated = 0; // faces with more than 3 corners (or with holes)
  // Faces ear clipping could not finish (self-intersecting, or too costly: a
  // huge polygon with few ears); their remainder is a fan that may overlap.
  size_t polygons_fanned = 0;
  size_t degenerate_triangles = 0;  // zero area or repeated vertex (kept)
  bool components_from_connectivity = false;
  // Surfaces with holes (CityJSON), and those of them whose triangles do not
  // cover exactly the outer ring minus the holes (a hole outside its outer
  // ring, overlapping holes, self-intersecting rings): kept as triangulated.
  size_t polygons_with_holes = 0;
  size_t polygons_holes_failed = 0;
  // Surfaces skipped because their outer ring has fewer than 3 distinct corners.
  size_t polygons_skipped = 0;
  // CityJSON: CityObjects with geometry but none at LoadOptions::cityjson_lod
  // (skipped), and geometries of a type without surfaces (MultiPoint,
  // MultiLineString) or unknown (skipped).
  size_t cityjson_objects_without_lod = 0;
  size_t cityjson_geometries_unsupported = 0;
  // CityJSON: the file's metadata.referenceSystem as it is written
  // ("urn:ogc:def:crs:EPSG::7415"; a value that is not a string as its JSON),
  // "" when it has none. The config's `crs` reads it (perclod/crs.h).
  std::string reference_system;
  double seconds = 0;
};

Scene load_scene(const std::string& path, const LoadOptions& options = {}, LoadReport* report = nullptr);

// The report as `info --json` and the run report print it ("polygons_fanned"
// only when some polygon was fanned, "reference_system" only when the file
// has one).
nlohmann::json load_report_json(const LoadReport& report);

// Mesh statistics for `perclod info`.
struct SceneInfo {
  size_t triangles = 0, vertices = 0, components = 0, materials = 0;
  size_t degenerate_triangles = 0;  // zero area or repeated vertex
  size_t non_manifold_edges = 0;    // edges (welded by position) with more than two faces
  size_t boundary_edges = 0;        // edges with exactly one face
  Bounds bounds;                    // recentred
  std::array<double, 3> offset{0, 0, 0};
};
SceneInfo analyse_scene(const Scene& scene);

// True for a triangle with a repeated index or zero area.
bool is_degenerate(const Scene& scene, size_t triangle);

}  // namespace perclod
