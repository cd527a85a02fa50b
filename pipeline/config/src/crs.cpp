// A model's CRS through PROJ: EPSG codes in their written forms, checked, and
// the local frame at a point (perclod/crs.h).
#include "perclod/crs.h"

#include <proj.h>

#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace perclod {
namespace {

// ---- EPSG codes as written ----

bool all_digits(const std::string& s) {
  if (s.empty() || s.size() > 9) return false;
  for (char ch : s)
    if (!std::isdigit(static_cast<unsigned char>(ch))) return false;
  return true;
}

// A version in a URN or URL: "", "0", "9.8.6".
bool is_version(const std::string& s) {
  for (char ch : s)
    if (!std::isdigit(static_cast<unsigned char>(ch)) && ch != '.') return false;
  return true;
}

std::string lower(std::string s) {
  for (char& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

std::string trimmed(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

// The digits after `prefix` and a version ended by `sep` ("urn:...:epsg:" +
// "9.8" + ":" + "7415"), or "" when `s` is not of that form.
std::string after_version(const std::string& s, const std::string& prefix, char sep) {
  if (s.rfind(prefix, 0) != 0) return "";
  const std::string rest = s.substr(prefix.size());
  const size_t at = rest.find(sep);
  if (at == std::string::npos || !is_version(rest.substr(0, at))) return "";
  return rest.substr(at + 1);
}

// ---- PROJ objects ----

struct ContextDeleter {
  void operator()(PJ_CONTEXT* c) const { proj_context_destroy(c); }
};
struct PjDeleter {
  void operator()(PJ* p) const { proj_destroy(p); }
};
using Context = std::unique_ptr<PJ_CONTEXT, ContextDeleter>;
using Pj = std::unique_ptr<PJ, PjDeleter>;

// A context of its own (PROJ's are not shared between threads), quiet: the
// errors are ours to word.
Context make_context() {
  Context ctx(proj_context_create());
  if (!ctx) throw std::runtime_error("PROJ: cannot create a context");
  proj_log_level(ctx.get(), PJ_LOG_NONE);
  return ctx;
}

std::string last_error(PJ_CONTEXT* ctx) {
  const int e = proj_context_errno(ctx);
  const char* s = e ? proj_context_errno_string(ctx, e) : nullptr;
  return s ? s : "no reason given";
}

// What a CRS type is called in an error.
std::string kind_of(PJ_TYPE t) {
  switch (t) {
    case PJ_TYPE_GEOGRAPHIC_2D_CRS:
    case PJ_TYPE_GEOGRAPHIC_3D_CRS:
    case PJ_TYPE_GEOGRAPHIC_CRS: return "geographic";
    case PJ_TYPE_VERTICAL_CRS: return "vertical";
    case PJ_TYPE_ENGINEERING_CRS: return "engineering (local)";
    case PJ_TYPE_TEMPORAL_CRS: return "temporal";
    default: return "not a projected, compound or geocentric";
  }
}

// Refuses a CRS whose coordinates are no metres on the Earth: a geographic
// one (degrees), a vertical or engineering one, and a compound one whose
// horizontal part is geographic.
void check_kind(PJ_CONTEXT* ctx, PJ* crs, const std::string& code) {
  PJ_TYPE t = proj_get_type(crs);
  if (t == PJ_TYPE_COMPOUND_CRS) {
    Pj horizontal(proj_crs_get_sub_crs(ctx, crs, 0));
    if (horizontal) t = proj_get_type(horizontal.get());
    if (t == PJ_TYPE_PROJECTED_CRS) return;
  }
  if (t == PJ_TYPE_PROJECTED_CRS || t == PJ_TYPE_GEOCENTRIC_CRS) return;
  std::string what = code + " (" + proj_get_name(crs) + ") is a " + kind_of(t) + " CRS";
  if (kind_of(t) == "geographic") what += ", in degrees";
  throw std::invalid_argument(what + ": perclod places models in a projected CRS (easting, northing and height in "
                                     "metres or feet), a compound one (projected + vertical) or a geocentric one");
}

// The CRS `text` names, checked (check_crs); `code` receives its EPSG code.
Pj source_crs(PJ_CONTEXT* ctx, const std::string& text, std::string& code) {
  code = epsg_code(text);
  if (code.empty())
    throw std::invalid_argument("'" + text + "' is not an EPSG code (EPSG:7415, 7415, urn:ogc:def:crs:EPSG::7415 or "
                                "https://www.opengis.net/def/crs/EPSG/0/7415)");
  Pj crs(proj_create(ctx, code.c_str()));
  if (!crs || !proj_is_crs(crs.get()))
    throw std::invalid_argument(code + " is not a CRS PROJ knows (" + last_error(ctx) +
                                "; see https://epsg.io or `projinfo " + code + "`)");
  check_kind(ctx, crs.get(), code);
  return crs;
}

// PROJ's transformation from `crs` to `target` ("EPSG:4979"), with its
// coordinates in easting, northing (longitude, latitude) order.
Pj transformation(PJ_CONTEXT* ctx, PJ* crs, const char* target, const std::string& code) {
  Pj to(proj_create(ctx, target));
  Pj op(to ? proj_create_crs_to_crs_from_pj(ctx, crs, to.get(), nullptr, nullptr) : nullptr);
  Pj normal(op ? proj_normalize_for_visualization(ctx, op.get()) : nullptr);
  if (!normal)
    throw std::invalid_argument(code + ": PROJ finds no transformation to " + target + " (" + last_error(ctx) + ")");
  return normal;
}

// Whether a projected or geocentric CRS has a third axis of its own (else
// its z is no height PROJ knows of: taken as ellipsoidal).
bool has_heights(PJ_CONTEXT* ctx, PJ* crs) {
  if (proj_get_type(crs) == PJ_TYPE_GEOCENTRIC_CRS) return true;
  Pj cs(proj_crs_get_coordinate_system(ctx, crs));
  return cs && proj_cs_get_axis_count(ctx, cs.get()) == 3;
}

// Source coordinates (model units) to WGS84 and ECEF by PROJ: the position
// by the transformation of the CRS's horizontal part, a compound CRS's
// height by the whole CRS's (crs.h says why).
class Placer {
 public:
  Placer(PJ_CONTEXT* ctx, PJ* crs, const std::string& code, double scale) : ctx_(ctx), code_(code), scale_(scale) {
    PJ* horizontal = crs;
    if (proj_get_type(crs) == PJ_TYPE_COMPOUND_CRS) {
      horizontal_crs_.reset(proj_crs_get_sub_crs(ctx, crs, 0));
      if (!horizontal_crs_) throw std::invalid_argument(code + ": PROJ gives no horizontal part of it");
      horizontal = horizontal_crs_.get();
      height_ = transformation(ctx, crs, "EPSG:4979", code);
      // Heights above the EGM96 geoid (EPSG:5773; Debian's proj-data has
      // its grid), for when the CRS's own geoid grid is missing.
      if (Pj egm96(proj_create(ctx, "EPSG:4326+5773")); egm96) try {
          egm96_ = transformation(ctx, egm96.get(), "EPSG:4979", "EPSG:5773");
        } catch (const std::invalid_argument&) {
        }
    }
    position_ = transformation(ctx, horizontal, "EPSG:4979", code);
    flat_ = !has_heights(ctx, horizontal);
    Pj wgs84(proj_create(ctx, "EPSG:4979"));
    cart_ = transformation(ctx, wgs84.get(), "EPSG:4978", "EPSG:4979");
  }

  // Longitude, latitude (degrees) and ellipsoidal height of `p`. A 2D
  // horizontal CRS's position does not move with z (PROJ would take z as a
  // height on its datum's ellipsoid, whose normal is not WGS84's), and its z
  // is the compound CRS's height, else an ellipsoidal height as it is.
  std::array<double, 3> wgs84(const std::array<double, 3>& p) const {
    const std::array<double, 3> q = {p[0] / scale_, p[1] / scale_, p[2] / scale_};
    if (!flat_) return through(position_.get(), q);
    std::array<double, 3> g = through(position_.get(), {q[0], q[1], 0});
    g[2] = height_ ? through(height_.get(), q)[2] : q[2];
    // A compound CRS whose geoid PROJ lacks (a ballpark vertical step) has
    // its heights taken as EGM96 heights: within a metre or two of most
    // national geoids, where ellipsoidal would be tens of metres off.
    if (height_ && egm96_ && is_ballpark(height_.get())) {
      const double h = through(egm96_.get(), {g[0], g[1], q[2]})[2];
      if (!is_ballpark(egm96_.get())) g[2] = h, egm96_used_ = true;
    }
    return g;
  }
  std::array<double, 3> ecef(const std::array<double, 3>& p) const { return through(cart_.get(), wgs84(p)); }

  // The transformations last used, into f.
  void describe(CrsFrame& f) const {
    Pj used(proj_trans_get_last_used_operation(position_.get()));
    PJ* o = used ? used.get() : position_.get();
    if (const char* name = proj_get_name(o)) f.operation = name;
    f.accuracy_m = proj_coordoperation_get_accuracy(ctx_, o);
    f.ballpark = proj_coordoperation_has_ballpark_transformation(ctx_, o) == 1;
    f.height_ballpark = flat_;
    if (!height_) return;
    Pj h(proj_trans_get_last_used_operation(height_.get()));
    PJ* ho = h ? h.get() : height_.get();
    if (const char* name = proj_get_name(ho)) f.height_operation = name;
    f.height_ballpark = proj_coordoperation_has_ballpark_transformation(ctx_, ho) == 1;
    if (egm96_used_) f.height_ballpark = false, f.height_fallback = "EGM96";
  }

 private:
  std::array<double, 3> through(PJ* op, const std::array<double, 3>& q) const {
    const PJ_COORD out = proj_trans(op, PJ_FWD, proj_coord(q[0], q[1], q[2], 0));
    const std::array<double, 3> r = {out.xyz.x, out.xyz.y, out.xyz.z};
    for (double v : r)
      if (!std::isfinite(v) || std::abs(v) > 1e10)
        throw std::invalid_argument(code_ + ": PROJ cannot transform the point (" + std::to_string(q[0]) + ", " +
                                    std::to_string(q[1]) + ", " + std::to_string(q[2]) +
                                    ") (outside the CRS's area of use, or the wrong CRS?)");
    return r;
  }

  // Whether the operation `op` last used has a ballpark step.
  bool is_ballpark(PJ* op) const {
    Pj used(proj_trans_get_last_used_operation(op));
    return proj_coordoperation_has_ballpark_transformation(ctx_, used ? used.get() : op) == 1;
  }

  PJ_CONTEXT* ctx_;
  std::string code_;
  double scale_;
  Pj horizontal_crs_, position_, height_, egm96_, cart_;
  bool flat_ = false;  // the horizontal CRS has no third axis
  mutable bool egm96_used_ = false;
};

// Model units along an axis between the points whose difference gives the
// frame's axes: far above PROJ's rounding, far below the Earth's curvature.
constexpr double kStep = 5.0;

}  // namespace

std::string epsg_code(const std::string& text) {
  const std::string s = lower(trimmed(text));
  std::string digits;
  if (all_digits(s)) digits = s;
  else if (s.rfind("epsg:", 0) == 0) digits = s.substr(5);
  else if (s.rfind("urn:", 0) == 0) digits = after_version(s, "urn:ogc:def:crs:epsg:", ':');
  else if (s.rfind("http", 0) == 0)
    for (const char* p : {"http://www.opengis.net/def/crs/epsg/", "https://www.opengis.net/def/crs/epsg/"})
      if (digits.empty()) digits = after_version(s, p, '/');
  if (!all_digits(digits)) return "";
  return "EPSG:" + std::to_string(std::stoul(digits));
}

void check_crs(const std::string& code) {
  static std::mutex mu;
  static std::map<std::string, std::string> checked;  // code -> "" or its error
  std::lock_guard<std::mutex> lock(mu);
  auto it = checked.find(code);
  if (it == checked.end()) {
    std::string error;
    try {
      Context ctx = make_context();
      std::string epsg;
      Pj crs = source_crs(ctx.get(), code, epsg);
      Placer(ctx.get(), crs.get(), epsg, 1.0);
    } catch (const std::invalid_argument& e) {
      error = e.what();
    }
    it = checked.emplace(code, error).first;
  }
  if (!it->second.empty()) throw std::invalid_argument(it->second);
}

CrsFrame crs_frame(const std::string& text, const std::array<double, 3>& point, double scale) {
  if (!(scale > 0) || !std::isfinite(scale)) throw std::invalid_argument("the unit scale must be a positive number");
  Context ctx = make_context();
  CrsFrame f;
  Pj crs = source_crs(ctx.get(), text, f.code);
  f.name = proj_get_name(crs.get());
  const Placer placer(ctx.get(), crs.get(), f.code, scale);
  f.origin = placer.ecef(point);
  // Central differences: exact for the linear part; the curvature's error
  // (kStep / Earth radius) is under a millionth.
  for (int i = 0; i < 3; ++i) {
    std::array<double, 3> ahead = point, behind = point;
    ahead[i] += kStep, behind[i] -= kStep;
    const auto a = placer.ecef(ahead), b = placer.ecef(behind);
    for (int r = 0; r < 3; ++r) f.axes[i][r] = (a[r] - b[r]) / (2 * kStep);
  }
  const auto g = placer.wgs84(point);
  f.lon = g[0], f.lat = g[1], f.height = g[2];
  placer.describe(f);
  return f;
}

}  // namespace perclod
