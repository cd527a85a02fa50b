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

namespace {

std::string fmt_deg(double v) {
  std::ostringstream ss;
  ss << v;
  return ss.str();
}

// "8" of "ring8..." and the elevations after "el" ("0/30/60"); false when
// `item` is not a ring.
bool parse_ring(const std::string& item, int& n, std::vector<double>& elevations) {
  if (item.rfind("ring", 0) != 0) return false;
  size_t e = item.find("el");
  std::string count = item.substr(4, e == std::string::npos ? std::string::npos : e - 4);
  size_t used = 0;
  try {
    long v = std::stol(count, &used);
    if (used != count.size() || v < 1 || v > 360) return false;
    n = int(v);
  } catch (const std::exception&) {
    return false;
  }
  elevations.clear();
  if (e == std::string::npos) {
    elevations = {0, 30, 60};
    return true;
  }
  std::stringstream ss(item.substr(e + 2));
  std::string el;
  while (std::getline(ss, el, '/')) {
    try {
      double v = std::stod(el, &used);
      if (used != el.size() || !(std::fabs(v) < 89.9)) return false;
      elevations.push_back(v);
    } catch (const std::exception&) {
      return false;
    }
  }
  return !elevations.empty();
}

}  // namespace

std::vector<std::string> parse_views(const std::vector<std::string>& list, UpAxis up) {
  std::vector<std::string> items;  // each item may itself be a comma list
  for (const auto& l : list) {
    std::stringstream ss(l);
    std::string f;
    bool any = false;
    while (std::getline(ss, f, ',')) items.push_back(f), any = true;
    if (!any) items.push_back(l);
  }
  const char h2 = up == UpAxis::Z ? 'y' : 'z';
  const std::vector<std::string> facades = {"+x", "-x", std::string("+") + h2, std::string("-") + h2};
  std::vector<std::string> out;
  auto add = [&](const std::string& v) {
    if (std::find(out.begin(), out.end(), v) == out.end()) out.push_back(v);
  };
  for (std::string f : items) {
    f.erase(0, f.find_first_not_of(" \t"));
    f.erase(f.find_last_not_of(" \t") + 1);
    double az, el;
    int n;
    std::vector<double> elevations;
    if (f == "all" || f == "facades") {
      for (const auto& v : facades) add(v);
    } else if (f == "obliques") {
      for (int a : {45, 135, 225, 315}) add("az" + std::to_string(a) + "el0");
    } else if (f == "top") {
      add("top");
    } else if (f == "held_out") {
      // Between the default set's azimuths (half its 45-degree step), low and
      // high in turn, and one steep view: none is a view of the default set.
      for (int i = 0; i < 8; ++i) add("az" + fmt_deg(22.5 + 45.0 * i) + "el" + (i % 2 ? "45" : "15"));
      add("az0el75");
    } else if (parse_ring(f, n, elevations)) {
      for (double e : elevations)
        for (int i = 0; i < n; ++i) add("az" + fmt_deg(360.0 * i / n) + "el" + fmt_deg(e));
    } else if ((f.size() == 2 && (f[0] == '+' || f[0] == '-') && (f[1] == 'x' || f[1] == h2)) ||
               (parse_free_view(f, az, el) && std::fabs(el) < 89.9)) {
      add(f);
    } else {
      throw std::invalid_argument("view '" + f + "' is not a preset (facades obliques top held_out ring<N>[el<E>/...]), a facade (+x -x +" +
                                  std::string(1, h2) + " -" + std::string(1, h2) +
                                  ") nor a view az<A>el<E> with |E| < 89.9, such as az30el15 (the up axis is " +
                                  (up == UpAxis::Z ? "z" : "y") + ")");
    }
  }
  if (out.empty()) throw std::invalid_argument("no view given");
  return out;
}

std::vector<std::string> parse_views(const std::string& spec, UpAxis up) {
  return parse_views(std::vector<std::string>{spec}, up);
}

namespace {
// The least and greatest eye depth of the box's corners along cam.forward.
void box_depths(const Camera& cam, const Bounds& b, double& dmin, double& dmax) {
  dmin = INFINITY, dmax = -INFINITY;
  for (int i = 0; i < 8; ++i) {
    Eigen::Vector3d corner(i & 1 ? b.hi[0] : b.lo[0], i & 2 ? b.hi[1] : b.lo[1], i & 4 ? b.hi[2] : b.lo[2]);
    double d = (corner - cam.eye).dot(cam.forward);
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
  }
}
double clip_margin(const Bounds& b) { return 0.01 * std::max(double(b.diagonal()), 1e-6); }
}  // namespace

double box_near_depth(const Camera& cam, const Bounds& b) {
  double dmin, dmax;
  box_depths(cam, b, dmin, dmax);
  return dmin - clip_margin(b);
}

void fit_clip_planes(Camera& cam, const Bounds& b) {
  double dmin, dmax;
  box_depths(cam, b, dmin, dmax);
  cam.zfar = std::max(dmax, 0.0) + clip_margin(b) + 1e-3;
  // Stay in front of the eye; a box that surrounds the eye clips at a small fraction of its size.
  cam.znear = std::max(dmin - clip_margin(b), std::max(1e-4 * cam.zfar, 1e-3));
}

Camera facade_camera(const Bounds& b, UpAxis up, const std::string& facade, double distance,
                     const DisplayProfile& display) {
  return view_camera(b, up, facade, distance, display);
}

std::string distance_problem(double distance) {
  std::ostringstream ss;
  if (!(distance > 0) || !std::isfinite(distance)) ss << "must be a positive number of metres, got " << distance;
  else if (distance > kMaxDistance)
    ss << distance << " m is farther than the " << kMaxDistance << " m perclod takes (a building is far below a pixel "
       << "there, and at larger distances its size is lost in the precision of the eye's coordinates)";
  return ss.str();
}

Camera view_camera(const Bounds& b, UpAxis up, const std::string& facade, double distance,
                   const DisplayProfile& display) {
  if (const std::string p = distance_problem(distance); !p.empty())
    throw std::invalid_argument("viewing distance: " + p);
  double az, el;
  if (parse_free_view(facade, az, el)) return free_camera(b, up, az, el, distance, display);
  if (facade == "top") {
    // From above, image up along the second horizontal axis (+y with Z up, -z with Y up).
    Eigen::Vector3d c = to_vec(b.center());
    Eigen::Vector3d eye = c;
    eye[up_index(up)] = b.hi[up_index(up)] + distance;
    Eigen::Vector3d h2 = up == UpAxis::Z ? Eigen::Vector3d(0, 1, 0) : Eigen::Vector3d(0, 0, -1);
    Camera cam = look_at(eye, c, h2, display.fov_y(), display.width, display.height, 0.1, 1.0);
    fit_clip_planes(cam, b);
    return cam;
  }
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
  if (const std::string p = distance_problem(distance); !p.empty())
    throw std::invalid_argument("viewing distance: " + p);
  if (std::fabs(el) >= 89.9) throw std::invalid_argument("elevation must be within (-89.9, 89.9) degrees");
  const double deg = kPi / 180.0;
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

std::vector<ViewTile> frame_view(const Bounds& b, UpAxis up, const std::string& view, double distance,
                                 const DisplayProfile& display, int max_tiles) {
  const Camera base = view_camera(b, up, view, distance, display);
  const double ty = base.tan_half_y(), tx = ty * base.aspect();
  double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY, zmin = INFINITY;
  bool fits = true;
  for (int i = 0; i < 8; ++i) {
    Eigen::Vector3d p(i & 1 ? b.hi[0] : b.lo[0], i & 2 ? b.hi[1] : b.lo[1], i & 4 ? b.hi[2] : b.lo[2]);
    Eigen::Vector3d d = p - base.eye;
    double u = d.dot(base.right), v = d.dot(base.up), z = d.dot(base.forward);
    umin = std::min(umin, u), umax = std::max(umax, u);
    vmin = std::min(vmin, v), vmax = std::max(vmax, v);
    zmin = std::min(zmin, z);
    fits = fits && z > 0 && std::fabs(u) <= z * tx && std::fabs(v) <= z * ty;
  }
  if (fits) return {{view, base}};
  // Each tile covers 2a x 2b of the camera plane at the nearest depth zmin
  // (and more behind it); centres spread so that neighbours overlap.
  // Less a pixel at each edge, so the box's outline is inside some frame and
  // not on an edge between pixel centres.
  const double a = zmin * tx * (1.0 - 2.0 / base.width), h = zmin * ty * (1.0 - 2.0 / base.height);
  if (!(a > 0 && h > 0))
    throw std::invalid_argument("view " + view + " at " + fmt_deg(distance) + " m: the eye is inside the model's box");
  const double nxd = std::ceil((umax - umin) / (2 * a)), nyd = std::ceil((vmax - vmin) / (2 * h));
  if (!(nxd * nyd <= max_tiles))
    throw std::invalid_argument("view " + view + " at " + fmt_deg(distance) + " m would need " + fmt_deg(nxd * nyd) +
                                " tiles to frame the model (more than " + std::to_string(max_tiles) +
                                "): the distance is too close for a model this size");
  const int nx = std::max(1, int(nxd)), ny = std::max(1, int(nyd));
  auto centre = [](double lo, double hi, double half, int n, int i) {
    return n == 1 ? 0.5 * (lo + hi) : lo + half + i * (hi - lo - 2 * half) / (n - 1);
  };
  std::vector<ViewTile> tiles;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      Camera cam = base;
      cam.eye += centre(umin, umax, a, nx, i) * base.right + centre(vmin, vmax, h, ny, j) * base.up;
      fit_clip_planes(cam, b);
      tiles.push_back({view + "_t" + std::to_string(tiles.size()), cam});
    }
  return tiles;
}

double display_pixel_footprint(const DisplayProfile& display, double distance) {
  Camera c;
  c.fov_y = display.fov_y();
  c.width = display.width;
  c.height = display.height;
  return c.pixel_footprint(distance);
}

void check_framing(const Bounds& bounds, UpAxis up, const DisplayProfile& display, const std::vector<std::string>& views,
                   const std::vector<double>& distances) {
  for (double d : distances)
    for (const auto& v : views) frame_view(bounds, up, v, d, display);
}

}  // namespace perclod
