// Facade and free views (docs/method.md section 1).
#include "perclod/views.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace perclod {
namespace {

Eigen::Vector3d up_vector(UpAxis up) { return up == UpAxis::Z ? Eigen::Vector3d(0, 0, 1) : Eigen::Vector3d(0, 1, 0); }
int up_index(UpAxis up) { return up == UpAxis::Z ? 2 : 1; }

Eigen::Vector3d to_vec(const std::array<float, 3>& a) { return {a[0], a[1], a[2]}; }

// "az30el15" -> (30, 15). False when `name` is not a free-view name.
bool parse_free_view(const std::string& name, double& az, double& el) {
  if (name.rfind("az", 0) != 0) return false;
  size_t e = name.find("el");
  if (e == std::string::npos) return false;
  try {
    size_t used = 0;
    az = std::stod(name.substr(2, e - 2), &used);
    if (used != e - 2) return false;
    el = std::stod(name.substr(e + 2), &used);
    return used == name.size() - e - 2;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

UpAxis parse_up_axis(const std::string& s) {
  if (s == "y" || s == "Y") return UpAxis::Y;
  if (s == "z" || s == "Z") return UpAxis::Z;
  throw std::invalid_argument("up axis must be 'y' or 'z', not '" + s + "'");
}

std::vector<std::string> parse_facades(const std::string& spec, UpAxis up) {
  const char h2 = up == UpAxis::Z ? 'y' : 'z';
  if (spec == "all") return {"+x", "-x", std::string("+") + h2, std::string("-") + h2};
  std::vector<std::string> out;
  std::stringstream ss(spec);
  std::string f;
  while (std::getline(ss, f, ',')) {
    double az, el;
    bool ok = (f.size() == 2 && (f[0] == '+' || f[0] == '-') && (f[1] == 'x' || f[1] == h2)) ||
              (parse_free_view(f, az, el) && std::fabs(el) < 89.9);
    if (!ok)
      throw std::invalid_argument("facade '" + f + "' is not one of +x -x +" + std::string(1, h2) + " -" +
                                  std::string(1, h2) + " all, nor a free view az<A>el<E> such as az30el15 (the up axis is " +
                                  (up == UpAxis::Z ? "z" : "y") + ")");
    out.push_back(f);
  }
  if (out.empty()) throw std::invalid_argument("no facade given");
  return out;
}

void fit_clip_planes(Camera& cam, const Bounds& b) {
  double dmin = INFINITY, dmax = -INFINITY;
  for (int i = 0; i < 8; ++i) {
    Eigen::Vector3d corner(i & 1 ? b.hi[0] : b.lo[0], i & 2 ? b.hi[1] : b.lo[1], i & 4 ? b.hi[2] : b.lo[2]);
    double d = (corner - cam.eye).dot(cam.forward);
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
  }
  double diag = std::max(double(b.diagonal()), 1e-6);
  cam.zfar = std::max(dmax, 0.0) + 0.01 * diag + 1e-3;
  // Stay in front of the eye; a box that surrounds the eye clips at a small fraction of its size.
  cam.znear = std::max(dmin - 0.01 * diag, std::max(1e-4 * cam.zfar, 1e-3));
}

Camera facade_camera(const Bounds& b, UpAxis up, const std::string& facade, double distance,
                     const DisplayProfile& display) {
  if (!(distance > 0)) throw std::invalid_argument("viewing distance must be positive");
  double az, el;
  if (parse_free_view(facade, az, el)) return free_camera(b, up, az, el, distance, display);
  if (facade.size() != 2) throw std::invalid_argument("bad facade name '" + facade + "'");
  int axis = facade.at(1) == 'x' ? 0 : facade[1] == 'y' ? 1 : 2;
  if (axis == up_index(up)) throw std::invalid_argument("facade '" + facade + "' is along the up axis");
  double sign = facade[0] == '-' ? -1.0 : 1.0;
  Eigen::Vector3d c = to_vec(b.center());
  Eigen::Vector3d eye = c;
  double face = sign > 0 ? b.hi[axis] : b.lo[axis];
  eye[axis] = face + sign * distance;
  Camera cam = look_at(eye, c, up_vector(up), display.fov_y(), display.width, display.height, 0.1, 1.0);
  fit_clip_planes(cam, b);
  return cam;
}

Camera free_camera(const Bounds& b, UpAxis up, double az, double el, double distance,
                   const DisplayProfile& display) {
  if (!(distance > 0)) throw std::invalid_argument("viewing distance must be positive");
  if (std::fabs(el) >= 89.9) throw std::invalid_argument("elevation must be within (-89.9, 89.9) degrees");
  const double deg = 3.14159265358979323846 / 180.0;
  Eigen::Vector3d c = to_vec(b.center());
  double radius = 0.5 * b.diagonal();
  Eigen::Vector3d h1(1, 0, 0), h2 = up == UpAxis::Z ? Eigen::Vector3d(0, 1, 0) : Eigen::Vector3d(0, 0, -1);
  Eigen::Vector3d dir = std::cos(el * deg) * (std::cos(az * deg) * h1 + std::sin(az * deg) * h2) +
                        std::sin(el * deg) * up_vector(up);
  Camera cam = look_at(c + dir * (radius + distance), c, up_vector(up), display.fov_y(), display.width,
                       display.height, 0.1, 1.0);
  fit_clip_planes(cam, b);
  return cam;
}

double display_pixel_footprint(const DisplayProfile& display, double distance) {
  Camera c;
  c.fov_y = display.fov_y();
  c.width = display.width;
  c.height = display.height;
  return c.pixel_footprint(distance);
}

}  // namespace perclod
