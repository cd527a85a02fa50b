// perclod/load.h - model files into a Scene.
//
// OBJ is read by perclod's own parser in double precision (Debian's assimp is
// built with float, which loses centimetres at UTM coordinates): the bounding
// box is found in double, positions are recentred on its centre and only then
// become float; Scene::offset keeps the centre. PLY, glTF/GLB, STL, IFC, DAE,
// FBX go through assimp (float; recentred the same way).
//
// Components: an OBJ's o/g groups, assimp's nodes/meshes; where a file has at
// most one, the connected parts after welding equal positions.
// Nothing is silently dropped: polygons are triangulated, zero-area and
// repeated-vertex triangles are kept and counted. NaN/inf coordinates,
// out-of-range indices, unreadable or empty files throw LoadError naming the
// file (and line) and what is wrong.
#pragma once

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "perclod/scene.h"

namespace perclod {

struct LoadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct LoadOptions {
  double scale = 1.0;  // unit scale applied to source coordinates (e.g. 0.001 for mm)
};

struct LoadReport {
  size_t polygons = 0;              // faces in the file
  size_t polygons_triangulated = 0; // faces with more than 3 corners
  // Faces ear clipping could not finish (self-intersecting, or too costly: a
  // huge polygon with few ears); their remainder is a fan that may overlap.
  size_t polygons_fanned = 0;
  size_t degenerate_triangles = 0;  // zero area or repeated vertex (kept)
  bool components_from_connectivity = false;
  double seconds = 0;
};

Scene load_scene(const std::string& path, const LoadOptions& options = {}, LoadReport* report = nullptr);

// The report as `info --json` and the run report print it ("polygons_fanned"
// only when some polygon was fanned).
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
