// pixel_rays.h - the float ray of a pixel, identical for every tracer (private).
#pragma once

#include "perclod/camera.h"

namespace perclod::detail {

// Direction through the centre of pixel (x, y), computed in double by
// Camera::ray_direction and rounded to float once. Every float tracer uses
// exactly this ray, so octree and Embree see bit-identical rays.
inline void pixel_direction(const Camera& c, int x, int y, float d[3]) {
  const Eigen::Vector3d v = c.ray_direction(x + 0.5, y + 0.5);
  d[0] = float(v.x());
  d[1] = float(v.y());
  d[2] = float(v.z());
}

inline void eye_float(const Camera& c, float o[3]) {
  o[0] = float(c.eye.x());
  o[1] = float(c.eye.y());
  o[2] = float(c.eye.z());
}

}  // namespace perclod::detail
