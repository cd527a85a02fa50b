// perclod/export.h - a Scene to a file, with the source offset restored.
// OBJ (+ MTL with material colours, one group per component; coordinates
// written in double as position + offset, in the source's axes; a `vn` per
// vertex normal) or GLB (float positions; the offset, in double, as the
// translation of a root node holding one mesh with a primitive per material
// colour, each with its own vertices, NORMALs and, as the EXT_mesh_features
// feature id, each vertex's component; the mesh's extras.feature_names name
// the ids; glTF's +Y up, so a Z-up source is turned (x, y, z) -> (x, z, -y)).
// Normals of both are split where faces turn by more than 30 degrees
// (docs/usage.md#export-for-viewers). Atomic: written to a temporary file,
// renamed.
#pragma once

#include <string>
#include <vector>

#include "perclod/scene.h"

namespace perclod {

struct ExportOptions {
  bool z_up = false;  // the source's up axis is +Z (GLB turns it to +Y up)
};

// Format from the extension: .obj or .glb. Throws naming the file on failure.
void export_scene(const Scene& scene, const std::string& path, const ExportOptions& options = {});

// Every LOD of a model in one GLB, finest first: a root node with the finest
// LOD's offset, holding the finest LOD's node, which carries the MSFT_lod
// extension (ids: the coarser LODs' nodes, in order) and, in its extras,
// MSFT_screencoverage: screen_coverage[i] is the fraction of the screen's
// height below which LOD i gives way to LOD i + 1 (the last: to nothing).
// One mesh per LOD node (a primitive per material), named names[i].
void export_lods_glb(const std::vector<const Scene*>& lods, const std::vector<std::string>& names,
                     const std::vector<double>& screen_coverage, const std::string& path,
                     const ExportOptions& options = {});

}  // namespace perclod
