// perclod/export.h - a Scene to a file, with the source offset restored.
// OBJ (+ MTL with material colours, one group per component; coordinates
// written in double as position + offset) or GLB (float positions, the offset
// as the root node's translation). Atomic: written to a temporary file, renamed.
#pragma once

#include <string>

#include "perclod/scene.h"

namespace perclod {

// Format from the extension: .obj or .glb. Throws naming the file on failure.
void export_scene(const Scene& scene, const std::string& path);

}  // namespace perclod
