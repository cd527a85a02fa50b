#include "geometry_checks.h"

#include <xmmintrin.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace perclod::detail {

uint32_t component_slots(const Scene& scene) {
  if (scene.triangle_count() == 0) return 0;
  if (scene.component.empty()) return 1;
  uint32_t m = 0;
  for (uint32_t c : scene.component) m = std::max(m, c);
  return m + 1;
}

void check_camera(const Camera& c) {
  if (c.width < 1 || c.height < 1)
    throw std::invalid_argument("camera: image size " + std::to_string(c.width) + "x" +
                                std::to_string(c.height) + " must be at least 1x1");
  if (!c.eye.allFinite() || !c.forward.allFinite() || !c.right.allFinite() || !c.up.allFinite())
    throw std::invalid_argument("camera: eye or axes are not finite");
  if (!(c.fov_y > 0 && c.fov_y < kPi))
    throw std::invalid_argument("camera: fov_y " + std::to_string(c.fov_y) +
                                " must lie in (0, pi)");
  if (!(std::isfinite(c.znear) && std::isfinite(c.zfar) && c.znear >= 0 && c.znear < c.zfar))
    throw std::invalid_argument("camera: clip range [" + std::to_string(c.znear) + ", " +
                                std::to_string(c.zfar) + "] must satisfy 0 <= znear < zfar");
}

DenormalsOff::DenormalsOff() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040); }
DenormalsOff::~DenormalsOff() { _mm_setcsr(saved_); }

}  // namespace perclod::detail
