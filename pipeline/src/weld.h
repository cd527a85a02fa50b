// Welding vertices by exact position, shared by the loader and scene analysis.
#pragma once

#include <cstdint>
#include <vector>

#include "perclod/scene.h"

namespace perclod {

// For every vertex, the index of the first vertex with bit-identical position.
std::vector<uint32_t> weld_exact(const Scene& scene);

// Per triangle, a component id from connectivity over the welded vertices;
// returns the number of components.
uint32_t connected_components(const Scene& scene, const std::vector<uint32_t>& weld,
                              std::vector<uint32_t>& component);

}  // namespace perclod
