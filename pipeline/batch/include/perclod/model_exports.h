// perclod/model_exports.h - the files a viewer loads for one model: the
// manifest (which distances each LOD serves), a GLB per LOD, the all-LOD GLB
// (MSFT_lod) and a 3D Tiles 1.1 tileset placed on the Earth by the model's
// CRS (PROJ) or by an ENU frame at crs_origin.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "perclod/config.h"
#include "perclod/crs.h"
#include "perclod/load.h"
#include "perclod/lods.h"
#include "perclod/outputs.h"
#include "perclod/run_model.h"

namespace perclod {

// The maximum screen-space error (pixels) the tileset's errors are set for:
// CesiumJS's default. A client using another refines each tile at
// (its maximum / this) times the distances below.
constexpr double kTilesetMaxScreenSpaceError = 16;

// The serving range of each LOD (sorted by distance;
// docs/usage.md#which-distances-a-lod-serves): a LOD made for distance d
// serves from d up to the next LOD's d (the last: no end, to = infinity);
// the finest also closer, from min(d, d_th). vd is its largest vertex
// displacement (metres) and d_th = vd / (pixel angle) its switch distance
// (Belblidia's d_th = f * vd / ps), where vd shrinks under a pixel.
// A tile's geometricError is from * S * 2 tan(fov_y / 2) / height_px
// (S = kTilesetMaxScreenSpaceError; the finest is a leaf, 0): a 3D Tiles
// client with maximum screen-space error S, on the display the LODs were
// made for, refines a LOD's tile exactly when the camera comes closer than
// the distance that LOD was made for.
struct LodRange {
  double distance = 0, displacement = 0, switch_distance = 0, from = 0, to = 0;
  double screen_coverage = 0;  // model diagonal / screen height at `to` (0 for the last)
  double geometric_error = 0;  // tileset: the error that switches at `from` (finest: 0)
};
std::vector<LodRange> lod_ranges(const std::vector<double>& distances, const std::vector<double>& displacements,
                                 double pixel_angle, double fov_y, int height_px, double diagonal);

// The local east-north-up frame at a WGS84 point, as the column-major 4x4
// transform (ENU metres -> ECEF metres) 3D Tiles takes.
std::array<double, 16> enu_to_ecef(double lat_deg, double lon_deg, double height);

// Where a model's CRS places it: the frame of config.crs, else of the
// CityJSON file's referenceSystem (load.reference_system), at the centre of
// its bounding box (scene.offset); none with crs_origin, crs: none, or no CRS.
// Throws std::runtime_error naming the model file and the code when the
// file's referenceSystem is no EPSG code or PROJ cannot place the centre.
std::optional<CrsFrame> model_crs_frame(const BatchConfig& config, const LoadReport& load, const Scene& scene);

// The tileset root's transform (column-major) for a model placed by `frame`,
// whose point is `centre` (model units, source axes): the tileset's +Z-up
// coordinates (source coordinates, turned as `up` says) to ECEF.
std::array<double, 16> crs_transform(const CrsFrame& frame, const std::array<double, 3>& centre, UpAxis up);

// Writes beside the report in job.label.out: a GLB per LOD (when the LODs are
// OBJ), <stem>_lods.glb (MSFT_lod), <stem>_tileset.json (3D Tiles 1.1) when
// config.tileset, and always <stem>_manifest.json (last: its presence marks
// the outputs complete). File names in them are relative to the folder.
// `frame` (model_crs_frame) places the tileset and enters the manifest.
nlohmann::json write_model_exports(const Scene& scene, const std::vector<Scene>& lods, const LodJob& job,
                                   const BatchConfig& config, const ModelRun& run, const ModelReport& report,
                                   const std::optional<CrsFrame>& frame);

// Writes `manifest` to out.manifest() (atomically) after recording in its
// "checksums" the hash (hash_file) of every file of the model's outputs: each
// <stem>_* file in out.dir but the manifest. Call it again after rewriting
// any of those files.
void write_manifest(const OutputNames& out, nlohmann::json& manifest);

}  // namespace perclod
