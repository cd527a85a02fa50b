// perclod/display.h - how an image is looked at (docs/method.md section 1).
#pragma once

#include <cmath>
#include <string>

namespace perclod {

struct DisplayProfile {
  std::string name = "paper-19in-lcd";
  int width = 1280, height = 1024;  // pixels
  double dpi = 86.27;               // pixel density r
  double viewer_distance = 0.5;     // observer distance v, metres
  double fov_y_override_deg = 0;    // > 0 replaces the natural field of view

  static constexpr double kPi = 3.14159265358979323846;

  // ppd = 2 v tan(0.5 deg) r / 0.0254  (29.64 for the default profile)
  double pixels_per_degree() const {
    return 2.0 * viewer_distance * std::tan(0.5 * kPi / 180.0) * dpi / 0.0254;
  }
  // Highest frequency the display carries, cycles/degree: 0.5 ppd.
  double f_max() const { return 0.5 * pixels_per_degree(); }
  // Natural vertical field of view (radians): the angle the screen subtends.
  double natural_fov_y() const {
    double h_m = height / dpi * 0.0254;
    return 2.0 * std::atan(h_m / (2.0 * viewer_distance));
  }
  double fov_y() const {
    return fov_y_override_deg > 0 ? fov_y_override_deg * kPi / 180.0 : natural_fov_y();
  }
};

}  // namespace perclod
