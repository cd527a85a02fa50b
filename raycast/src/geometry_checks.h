// geometry_checks.h - input validation shared by the tracers (private).
#pragma once

#include <cstdint>

#include "perclod/camera.h"
#include "perclod/scene.h"

namespace perclod::detail {

// Number of components: max component id + 1 (0 for an empty scene). When
// Scene::component is empty every triangle counts as component 0.
uint32_t component_slots(const Scene& scene);

// Throws std::invalid_argument for width/height < 1, non-finite vectors, or
// a clip range that is not 0 <= znear < zfar (both finite).
void check_camera(const Camera& camera);

// Sets FTZ/DAZ on the calling thread (Embree's advice for tracing threads);
// restores the previous mode on destruction.
class DenormalsOff {
 public:
  DenormalsOff();
  ~DenormalsOff();
  DenormalsOff(const DenormalsOff&) = delete;
  DenormalsOff& operator=(const DenormalsOff&) = delete;

 private:
  unsigned int saved_;
};

}  // namespace perclod::detail
