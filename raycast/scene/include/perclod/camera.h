// perclod/camera.h - the one camera the renderer and the ray caster share.
//
// A pinhole camera in double precision. Conventions, used everywhere in perclod:
//  * image W x H, pixel (x, y) covers [x, x+1) x [y, y+1), its centre is
//    (x + 0.5, y + 0.5) (OpenGL's sampling point), row 0 is the TOP row;
//  * camera space looks down -z; `right` = +x, `up` = +y;
//  * ray_direction() is NOT normalised: its camera-space z is -1, so a hit's
//    ray parameter t equals its eye depth and [znear, zfar] are the clip planes;
//  * projection() is reversed-Z with a [0, 1] depth range (glClipControl
//    GL_ZERO_TO_ONE): depth 1 at znear, 0 at zfar;
//  * shift_x, shift_y (pixels, default 0) move the sampling point inside each
//    pixel: pixel (x, y) samples the unshifted camera's image point
//    (x + 0.5 + shift_x, y + 0.5 + shift_y). The renderer and every tracer
//    honour it (an off-axis frustum), which is how several samples per pixel
//    are taken (perclod/views.h, sample_offsets) without a second camera type.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace perclod {

struct Camera {
  Eigen::Vector3d eye{0, 0, 0};
  Eigen::Vector3d forward{0, 0, -1};  // unit, view direction
  Eigen::Vector3d right{1, 0, 0};     // unit
  Eigen::Vector3d up{0, 1, 0};        // unit
  double fov_y = 0.5;                 // vertical field of view, radians
  int width = 1, height = 1;
  double znear = 0.1, zfar = 1000.0;
  double shift_x = 0.0, shift_y = 0.0;  // sub-pixel sampling offset, pixels (see above)

  double tan_half_y() const { return std::tan(0.5 * fov_y); }
  double aspect() const { return double(width) / double(height); }

  // Direction through image point (px, py) (pixel centre = x + 0.5), with unit
  // component along `forward`.
  Eigen::Vector3d ray_direction(double px, double py) const {
    double th = tan_half_y();
    double sx = (2.0 * (px + shift_x) / width - 1.0) * th * aspect();
    double sy = (1.0 - 2.0 * (py + shift_y) / height) * th;
    return forward + sx * right + sy * up;
  }

  // World point -> image point (px, py) and eye depth. False when behind the eye.
  bool project(const Eigen::Vector3d& p, double& px, double& py, double& depth) const {
    Eigen::Vector3d d = p - eye;
    depth = d.dot(forward);
    if (depth <= 0) return false;
    double th = tan_half_y();
    double sx = d.dot(right) / depth / (th * aspect());
    double sy = d.dot(up) / depth / th;
    px = (sx + 1.0) * 0.5 * width - shift_x;
    py = (1.0 - sy) * 0.5 * height - shift_y;
    return true;
  }

  // World -> camera (OpenGL convention, looking down -z).
  Eigen::Matrix4d view() const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<1, 3>(0, 0) = right.transpose();
    m.block<1, 3>(1, 0) = up.transpose();
    m.block<1, 3>(2, 0) = -forward.transpose();
    m(0, 3) = -right.dot(eye);
    m(1, 3) = -up.dot(eye);
    m(2, 3) = forward.dot(eye);
    return m;
  }

  // Camera -> clip, reversed-Z into [0, 1]: z_ndc = n/(f-n) + n f / ((f-n) * (-z_e)) ... i.e.
  // depth 1 at -z_e = znear and 0 at -z_e = zfar.
  Eigen::Matrix4d projection() const {
    double th = tan_half_y();
    double n = znear, f = zfar;
    Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
    m(0, 0) = 1.0 / (th * aspect());
    m(1, 1) = 1.0 / th;
    m(0, 2) = 2.0 * shift_x / width;  // off-axis: image point x + shift_x lands on pixel x
    m(1, 2) = -2.0 * shift_y / height;
    m(2, 2) = n / (f - n);
    m(2, 3) = n * f / (f - n);
    m(3, 2) = -1.0;
    return m;
  }

  // Pixel footprint at eye depth d (metres per pixel): p(d) = 2 d tan(fov_y/2) / H.
  double pixel_footprint(double d) const { return 2.0 * d * tan_half_y() / height; }
};

// The part [x0, x0 + w) x [y0, y0 + h) of `c`'s image as a camera of its own:
// its pixel (x, y) samples what `c`'s pixel (x0 + x, y0 + y) samples (same
// eye, axes and pixel pitch; the window is an off-axis shift). Rendering or
// tracing a crop costs its own pixels, not the whole image's.
inline Camera cropped(const Camera& c, int x0, int y0, int w, int h) {
  Camera out = c;
  out.width = w;
  out.height = h;
  out.fov_y = 2.0 * std::atan(c.tan_half_y() * double(h) / double(c.height));
  out.shift_x = c.shift_x + x0 + 0.5 * (w - c.width);
  out.shift_y = c.shift_y + y0 + 0.5 * (h - c.height);
  return out;
}

// `c` at s times its resolution per axis: the same frustum, each pixel split
// into s x s. Fine pixel (s x + a, s y + b) samples what `c`'s pixel (x, y)
// samples with its shift moved by ((a + 0.5) / s - 0.5, (b + 0.5) / s - 0.5),
// so one render holds s x s renders of `c` at those sub-pixel offsets.
inline Camera refined(const Camera& c, int s) {
  Camera out = c;
  out.width = c.width * s;
  out.height = c.height * s;
  out.shift_x = c.shift_x * s;
  out.shift_y = c.shift_y * s;
  return out;
}

// A camera at `eye` looking at `target`; `world_up` must not be parallel to the view.
inline Camera look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                      const Eigen::Vector3d& world_up, double fov_y, int width, int height,
                      double znear, double zfar) {
  Camera c;
  c.eye = eye;
  c.forward = (target - eye).normalized();
  c.right = c.forward.cross(world_up).normalized();
  c.up = c.right.cross(c.forward);
  c.fov_y = fov_y;
  c.width = width;
  c.height = height;
  c.znear = znear;
  c.zfar = zfar;
  return c;
}

}  // namespace perclod
