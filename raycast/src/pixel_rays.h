// pixel_rays.h - the float ray of a pixel, identical for every tracer (private).
#pragma once

#include <vector>

#include "perclod/camera.h"

namespace perclod::detail {

// Direction through the sampling point of pixel (x, y) (its centre unless
// the camera is shifted), computed in double by
// Camera::ray_direction and rounded to float once. Every float tracer uses
// exactly this ray, so octree and Embree see bit-identical rays.
inline void pixel_direction(const Camera& c, int x, int y, float d[3]) {
  const Eigen::Vector3d v = c.ray_direction(x + 0.5, y + 0.5);
  d[0] = float(v.x());
  d[1] = float(v.y());
  d[2] = float(v.z());
}

// The same directions for a whole image without a tan() per pixel: the
// per-column and per-row screen offsets are computed once with the exact
// expressions of Camera::ray_direction, so direction() is bit-identical to
// pixel_direction().
class PixelDirections {
 public:
  explicit PixelDirections(const Camera& c) : cam_(c), sx_(size_t(c.width)), sy_(size_t(c.height)) {
    const double th = c.tan_half_y();
    for (int x = 0; x < c.width; ++x) sx_[size_t(x)] = (2.0 * (x + 0.5 + c.shift_x) / c.width - 1.0) * th * c.aspect();
    for (int y = 0; y < c.height; ++y) sy_[size_t(y)] = (1.0 - 2.0 * (y + 0.5 + c.shift_y) / c.height) * th;
  }
  void direction(int x, int y, float d[3]) const {
    const double sx = sx_[size_t(x)], sy = sy_[size_t(y)];
    for (int k = 0; k < 3; ++k) d[k] = float(cam_.forward[k] + sx * cam_.right[k] + sy * cam_.up[k]);
  }
  // direction() of pixels x0 .. x0 + n - 1 of row y, by component (the same
  // expression, evaluated in the same order).
  void row(int x0, int n, int y, float* dx, float* dy, float* dz) const {
    const double sy = sy_[size_t(y)];
    const double f[3] = {cam_.forward[0], cam_.forward[1], cam_.forward[2]};
    const double r[3] = {cam_.right[0], cam_.right[1], cam_.right[2]};
    const double u[3] = {sy * cam_.up[0], sy * cam_.up[1], sy * cam_.up[2]};
    const double* sx = sx_.data() + x0;
    for (int i = 0; i < n; ++i) {
      dx[i] = float(f[0] + sx[i] * r[0] + u[0]);
      dy[i] = float(f[1] + sx[i] * r[1] + u[1]);
      dz[i] = float(f[2] + sx[i] * r[2] + u[2]);
    }
  }

 private:
  const Camera& cam_;
  std::vector<double> sx_, sy_;
};

inline void eye_float(const Camera& c, float o[3]) {
  o[0] = float(c.eye.x());
  o[1] = float(c.eye.y());
  o[2] = float(c.eye.z());
}

}  // namespace perclod::detail
