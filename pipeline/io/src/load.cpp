// Model loading. OBJ: perclod's own double-precision reader. Other formats:
// assimp. Both end in build_scene(), which recentres in double and only then
// converts to float.
#include "perclod/load.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "perclod/simplify.h"

namespace perclod {
namespace fs = std::filesystem;
namespace {

// The file as read, before recentring: double positions, polygons already triangulated.
struct RawModel {
  std::vector<double> positions;  // xyz
  std::vector<uint32_t> indices;
  std::vector<uint32_t> component, material;
  std::vector<std::string> component_names;
  std::vector<Material> materials;
  // Components are the file's objects even when there is only one (CityJSON:
  // one per CityObject); else a file with at most one group gets connected parts.
  bool objects_are_components = false;
};

[[noreturn]] void fail(const std::string& path, const std::string& what, size_t line = 0) {
  if (line) throw LoadError(path + ":" + std::to_string(line) + ": " + what);
  throw LoadError(path + ": " + what);
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "no such file");
  if (fs::is_directory(path, ec)) fail(path, "is a directory, not a model file");
  std::ifstream f(path, std::ios::binary);
  if (!f) fail(path, "cannot open (permission?)");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string lower_extension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  for (auto& ch : e) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return e;
}

// ---------------------------------------------------------------- polygons

// Polygons with more corners than this are clipped by triangulate_large:
// ear clipping below restarts its scan after every ear and tests every
// corner, O(n^2) or worse (one 100k-corner polygon took 35 s).
constexpr size_t kLargePolygon = 1000;

// Ear clipping in near-linear time for large polygons: a linked ring that
// walks on after each ear (never rescanning from the start), and an ear test
// against the reflex corners only (a convex corner cannot lie inside an ear),
// found through a uniform grid. Same ear rule as triangulate(); gives up to a
// fan the same way when no ear is left, or when a work budget linear in the
// corner count is spent (hostile shapes: the rest is a fan, possibly overlapping).
template <class FX, class FY, class FC>
bool triangulate_large(const std::vector<uint32_t>& poly, const FX& X, const FY& Y, const FC& cross,
                       std::vector<uint32_t>& out) {
  const size_t n = poly.size();
  std::vector<uint32_t> prev(n), next(n);
  std::vector<char> alive(n, 1), reflex(n, 0);
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (size_t i = 0; i < n; ++i) {
    prev[i] = uint32_t((i + n - 1) % n), next[i] = uint32_t((i + 1) % n);
    lo[0] = std::min(lo[0], X(poly[i])), hi[0] = std::max(hi[0], X(poly[i]));
    lo[1] = std::min(lo[1], Y(poly[i])), hi[1] = std::max(hi[1], Y(poly[i]));
  }
  auto corner_cross = [&](uint32_t i) { return cross(poly[prev[i]], poly[i], poly[next[i]]); };
  const int side = std::max(1, int(std::sqrt(double(n))));
  const double cw = std::max(hi[0] - lo[0], 1e-300) / side, ch = std::max(hi[1] - lo[1], 1e-300) / side;
  auto cell = [&](double v, double l, double c) { return std::clamp(int((v - l) / c), 0, side - 1); };
  std::vector<std::vector<uint32_t>> grid(size_t(side) * side);
  size_t reflex_left = 0;
  for (uint32_t i = 0; i < n; ++i)
    if (corner_cross(i) <= 0) {
      reflex[i] = 1, ++reflex_left;
      grid[size_t(cell(Y(poly[i]), lo[1], ch)) * side + cell(X(poly[i]), lo[0], cw)].push_back(i);
    }
  // Work budget (ear tests, grid cells and corners visited): shapes such as
  // spirals have only a few ears at a time and would still clip in O(n^2).
  // Once spent, the rest becomes a fan, as when no ear is left.
  long long budget = 200LL * (long long)n;
  auto is_ear = [&](uint32_t b) {
    const uint32_t ia = prev[b], ic = next[b];
    const uint32_t a = poly[ia], v = poly[b], c = poly[ic];
    --budget;
    if (cross(a, v, c) <= 0) return false;  // reflex or flat corner
    if (reflex_left == 0) return true;
    const int x0 = cell(std::min({X(a), X(v), X(c)}), lo[0], cw), x1 = cell(std::max({X(a), X(v), X(c)}), lo[0], cw);
    const int y0 = cell(std::min({Y(a), Y(v), Y(c)}), lo[1], ch), y1 = cell(std::max({Y(a), Y(v), Y(c)}), lo[1], ch);
    budget -= (long long)(y1 - y0 + 1) * (x1 - x0 + 1);
    if (budget < 0) return false;
    for (int gy = y0; gy <= y1; ++gy)
      for (int gx = x0; gx <= x1; ++gx)
        for (uint32_t j : grid[size_t(gy) * side + gx]) {
          --budget;
          if (!alive[j] || !reflex[j]) continue;
          const uint32_t q = poly[j];
          if (q == a || q == v || q == c) continue;
          if (cross(a, v, q) >= 0 && cross(v, c, q) >= 0 && cross(c, a, q) >= 0) return false;
        }
    return true;
  };
  size_t left = n;
  uint32_t cur = 0, stop = 0;
  bool first = true;
  while (left > 3 && budget > 0) {
    if (!first && cur == stop) break;  // a whole turn without an ear
    first = false;
    if (!is_ear(cur)) {
      cur = next[cur];
      continue;
    }
    const uint32_t a = prev[cur], c = next[cur];
    out.insert(out.end(), {poly[a], poly[cur], poly[c]});
    alive[cur] = 0;
    if (reflex[cur]) reflex[cur] = 0, --reflex_left;
    next[a] = c, prev[c] = a;
    --left;
    for (uint32_t k : {a, c})
      if (reflex[k] && corner_cross(k) > 0) reflex[k] = 0, --reflex_left;  // a reflex corner turned convex
    cur = next[c];  // walk on: strips, not a fan of ever longer triangles
    stop = cur, first = true;
  }
  // Whatever is left: a fan, as in triangulate().
  std::vector<uint32_t> ring;
  for (uint32_t i = cur, k = 0; k < left; ++k, i = next[i]) ring.push_back(poly[i]);
  for (size_t i = 1; i + 1 < ring.size(); ++i) out.insert(out.end(), {ring[0], ring[i], ring[i + 1]});
  return ring.size() > 3;
}

// Newell normal of a ring (indices into pos): its direction is the ring's
// facing (counter-clockwise seen from the tip), its length twice the area.
std::array<double, 3> newell(const std::vector<double>& pos, const std::vector<uint32_t>& ring) {
  auto P = [&](uint32_t i, int a) { return pos[3 * size_t(i) + a]; };
  std::array<double, 3> nrm{0, 0, 0};
  for (size_t i = 0, n = ring.size(); i < n; ++i) {
    uint32_t a = ring[i], b = ring[(i + 1) % n];
    nrm[0] += (P(a, 1) - P(b, 1)) * (P(a, 2) + P(b, 2));
    nrm[1] += (P(a, 2) - P(b, 2)) * (P(a, 0) + P(b, 0));
    nrm[2] += (P(a, 0) - P(b, 0)) * (P(a, 1) + P(b, 1));
  }
  return nrm;
}

// The 2D frame polygons are clipped in: the axis plane most perpendicular to
// a normal, mirrored (s) so a ring counter-clockwise about the normal stays
// counter-clockwise.
struct Plane2 {
  int ax = 0, ay = 1;
  double s = 1;
};
Plane2 plane_of(const std::array<double, 3>& nrm) {
  const double nx = nrm[0], ny = nrm[1], nz = nrm[2];
  Plane2 p;
  double sign = nz;
  if (std::fabs(nx) >= std::fabs(ny) && std::fabs(nx) >= std::fabs(nz)) p.ax = 1, p.ay = 2, sign = nx;
  else if (std::fabs(ny) >= std::fabs(nz)) p.ax = 2, p.ay = 0, sign = ny;
  p.s = sign >= 0 ? 1.0 : -1.0;
  return p;
}

// Triangulates polygon `poly` (indices into pos) by ear clipping in the plane
// of its Newell normal (or of `normal`, when given: a ring with holes bridged
// in is clipped in its outer ring's plane); falls back to a fan if the polygon
// is self-intersecting (or too costly to clip); returns whether that fallback
// fanned over 3 corners.
bool triangulate(const std::vector<double>& pos, const std::vector<uint32_t>& poly,
                 std::vector<uint32_t>& out, const std::array<double, 3>* normal = nullptr) {
  size_t n = poly.size();
  if (n == 3) {
    out.insert(out.end(), poly.begin(), poly.end());
    return false;
  }
  auto P = [&](uint32_t i, int a) { return pos[3 * size_t(i) + a]; };
  // Project onto the plane most perpendicular to the normal, keeping orientation.
  const Plane2 pl = plane_of(normal ? *normal : newell(pos, poly));
  const int ax = pl.ax, ay = pl.ay;
  const double s = pl.s;
  auto X = [&](uint32_t i) { return P(i, ax); };
  auto Y = [&](uint32_t i) { return P(i, ay) * s; };
  auto cross = [&](uint32_t a, uint32_t b, uint32_t c) {
    return (X(b) - X(a)) * (Y(c) - Y(a)) - (Y(b) - Y(a)) * (X(c) - X(a));
  };
  if (n > kLargePolygon) return triangulate_large(poly, X, Y, cross, out);
  std::vector<uint32_t> ring(poly);
  size_t guard = 0;
  while (ring.size() > 3 && guard < 4 * n * n) {
    bool clipped = false;
    size_t m = ring.size();
    for (size_t i = 0; i < m; ++i, ++guard) {
      uint32_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
      if (cross(a, b, c) <= 0) continue;  // reflex or flat corner
      bool inside = false;
      for (size_t j = 0; j < m && !inside; ++j) {
        uint32_t q = ring[j];
        if (q == a || q == b || q == c) continue;
        inside = cross(a, b, q) >= 0 && cross(b, c, q) >= 0 && cross(c, a, q) >= 0;
      }
      if (inside) continue;
      out.insert(out.end(), {a, b, c});
      ring.erase(ring.begin() + long(i));
      clipped = true;
      break;
    }
    if (!clipped) break;
  }
  // Whatever is left (3 corners, or a polygon ear clipping could not handle): a fan.
  for (size_t i = 1; i + 1 < ring.size(); ++i) out.insert(out.end(), {ring[0], ring[i], ring[i + 1]});
  return ring.size() > 3;
}

// ---------------------------------------------------------------- OBJ

struct LineCursor {
  const char* p;
  const char* end;
  void skip_space() {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  }
  bool at_end() {
    skip_space();
    return p >= end;
  }
  std::string_view word() {
    skip_space();
    const char* b = p;
    while (p < end && *p != ' ' && *p != '\t' && *p != '\r') ++p;
    return {b, size_t(p - b)};
  }
  std::string rest() {
    skip_space();
    const char* e = end;
    while (e > p && (e[-1] == ' ' || e[-1] == '\r' || e[-1] == '\t')) --e;
    return std::string(p, e);
  }
};

bool parse_double(std::string_view w, double& v) {
  if (!w.empty() && w[0] == '+') w.remove_prefix(1);
  auto r = std::from_chars(w.data(), w.data() + w.size(), v);
  return r.ec == std::errc() && r.ptr == w.data() + w.size();
}

// A whole integer, nothing after it ("2x" and "1.5" are not).
bool parse_long(std::string_view w, long& v) {
  auto r = std::from_chars(w.data(), w.data() + w.size(), v);
  return r.ec == std::errc() && r.ptr == w.data() + w.size();
}

// A face corner "v", "v/vt", "v//vn" or "v/vt/vn": every part a whole
// integer (only vt may be left out, and only before "/vn"), v non-zero.
bool parse_corner(std::string_view w, long& vertex) {
  std::string_view parts[4];
  int n = 0;
  for (size_t slash; n < 4; w.remove_prefix(slash + 1)) {
    slash = w.find('/');
    parts[n++] = w.substr(0, slash);
    if (slash == std::string_view::npos) break;
  }
  if (n > 3 || !parse_long(parts[0], vertex) || vertex == 0) return false;
  long unused;
  for (int i = 1; i < n; ++i)
    if (!(i == 1 && n == 3 && parts[i].empty()) && !parse_long(parts[i], unused)) return false;
  return true;
}

void read_mtl(const std::string& path, std::map<std::string, std::array<float, 3>>& colors) {
  std::ifstream f(path);
  if (!f) return;  // a missing MTL only loses colours; components still colour the render
  std::string line, current;
  while (std::getline(f, line)) {
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "newmtl") {
      std::getline(ss >> std::ws, current);
      while (!current.empty() && (current.back() == '\r' || current.back() == ' ')) current.pop_back();
    } else if (key == "Kd" && !current.empty()) {
      std::array<float, 3> c{};
      if (ss >> c[0] >> c[1] >> c[2]) colors[current] = c;
    }
  }
}

RawModel read_obj(const std::string& path, LoadReport& rep) {
  std::string text = read_file(path);
  RawModel m;
  std::map<std::string, uint32_t> comp_ids, mat_ids;
  std::map<std::string, std::array<float, 3>> mtl_colors;
  uint32_t comp = UINT32_MAX, mat = UINT32_MAX;
  auto component_id = [&](const std::string& name) {
    auto [it, added] = comp_ids.try_emplace(name, uint32_t(m.component_names.size()));
    if (added) m.component_names.push_back(name);
    return it->second;
  };
  std::vector<uint32_t> poly;
  size_t line_no = 0;
  const char* p = text.data();
  const char* end = p + text.size();
  while (p < end) {
    const char* eol = static_cast<const char*>(memchr(p, '\n', size_t(end - p)));
    if (!eol) eol = end;
    ++line_no;
    LineCursor c{p, eol};
    p = eol + 1;
    std::string_view key = c.word();
    if (key == "v") {
      for (int a = 0; a < 3; ++a) {
        double v;
        std::string_view w = c.word();
        if (!parse_double(w, v)) fail(path, "vertex coordinate '" + std::string(w) + "' is not a number", line_no);
        if (!std::isfinite(v)) fail(path, "vertex coordinate is " + std::string(w) + " (NaN/inf)", line_no);
        m.positions.push_back(v);
      }
    } else if (key == "f") {
      poly.clear();
      size_t nv = m.positions.size() / 3;
      while (!c.at_end()) {
        std::string_view w = c.word();
        long idx = 0;
        if (!parse_corner(w, idx))
          fail(path, "face corner '" + std::string(w) + "' is not a vertex index", line_no);
        long resolved = idx > 0 ? idx - 1 : long(nv) + idx;  // negative: relative to the end
        if (resolved < 0 || resolved >= long(nv))
          fail(path, "face index " + std::to_string(idx) + " out of range (" + std::to_string(nv) +
                         " vertices so far)", line_no);
        poly.push_back(uint32_t(resolved));
      }
      ++rep.polygons;
      if (poly.size() < 3)
        fail(path, "face with " + std::to_string(poly.size()) + " corner(s); a face needs 3", line_no);
      if (poly.size() > 3) ++rep.polygons_triangulated;
      if (comp == UINT32_MAX) comp = component_id("default");
      if (mat == UINT32_MAX) {
        mat = uint32_t(m.materials.size());
        m.materials.push_back({"default", {0.8f, 0.8f, 0.8f}, false});
      }
      size_t before = m.indices.size();
      rep.polygons_fanned += triangulate(m.positions, poly, m.indices);
      for (size_t t = before / 3; t < m.indices.size() / 3; ++t) {
        m.component.push_back(comp);
        m.material.push_back(mat);
      }
    } else if (key == "o" || key == "g") {
      std::string name = c.rest();
      comp = component_id(name.empty() ? "default" : name);
    } else if (key == "usemtl") {
      std::string name = c.rest();
      auto [it, added] = mat_ids.try_emplace(name, uint32_t(m.materials.size()));
      if (added) m.materials.push_back({name, {0.8f, 0.8f, 0.8f}, false});
      mat = it->second;
    } else if (key == "mtllib") {
      read_mtl((fs::path(path).parent_path() / c.rest()).string(), mtl_colors);
    }
    // vt, vn, s, l, p and comments carry nothing perclod uses.
  }
  for (auto& mt : m.materials) {
    auto it = mtl_colors.find(mt.name);
    if (it != mtl_colors.end()) mt.color = it->second, mt.has_color = true;
  }
  return m;
}

// A file without an extension is read as OBJ (in double precision, like any
// .obj) if its first statements are OBJ statements and one is a vertex.
bool looks_like_obj(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::string head(65536, '\0');
  f.read(head.data(), std::streamsize(head.size()));
  head.resize(size_t(f.gcount()));
  std::istringstream lines(head);
  std::string line;
  bool vertex = false;
  for (int n = 0; n < 200 && std::getline(lines, line); ++n) {
    std::istringstream ls(line);
    std::string key;
    if (!(ls >> key) || key[0] == '#') continue;
    static const char* kObj[] = {"v", "vt", "vn", "vp", "f", "l", "p", "g", "o", "s", "usemtl", "mtllib"};
    if (std::find(std::begin(kObj), std::end(kObj), key) == std::end(kObj)) return false;
    vertex |= key == "v";
  }
  return vertex;
}

// ---------------------------------------------------------------- polygons with holes

// Joins `hole` into `ring` (both indices into pos, in the 2D frame X/Y where
// ring is counter-clockwise and hole clockwise) by a bridge edge, so the
// result is one ring ear clipping can take: ..., P, M, hole..., M, P, ...
// M is the hole's rightmost corner; P a ring corner M sees, found by casting
// a ray from M towards +x: the nearer end of the first edge it meets, unless
// a reflex corner inside the triangle (M, hit, that end) hides it, then the
// hiding corner closest in angle to the ray. Returns false when the ray meets
// no edge (a hole outside its outer ring): the hole is then left out.
template <class FX, class FY>
bool bridge_hole(std::vector<uint32_t>& ring, const std::vector<uint32_t>& hole, const FX& X, const FY& Y) {
  const size_t h = hole.size(), n = ring.size();
  size_t mi = 0;
  for (size_t i = 1; i < h; ++i)
    if (X(hole[i]) > X(hole[mi]) || (X(hole[i]) == X(hole[mi]) && Y(hole[i]) < Y(hole[mi]))) mi = i;
  const double mx = X(hole[mi]), my = Y(hole[mi]);
  double hit = INFINITY;
  size_t edge = SIZE_MAX;
  for (size_t k = 0; k < n; ++k) {
    const uint32_t a = ring[k], b = ring[(k + 1) % n];
    const double ay = Y(a), by = Y(b);
    if ((ay < my && by < my) || (ay > my && by > my)) continue;
    double x;
    if (ay == by) {  // along the ray: its nearer end ahead of M
      const double lo = std::min(X(a), X(b)), hi = std::max(X(a), X(b));
      x = lo >= mx ? lo : hi;
    } else {
      x = X(a) + (my - ay) * (X(b) - X(a)) / (by - ay);
    }
    if (x >= mx && x < hit) hit = x, edge = k;
  }
  if (edge == SIZE_MAX) return false;
  const size_t ka = edge, kb = (edge + 1) % n;
  size_t pk;
  if (X(ring[ka]) == hit && Y(ring[ka]) == my) pk = ka;
  else if (X(ring[kb]) == hit && Y(ring[kb]) == my) pk = kb;
  else pk = X(ring[ka]) > X(ring[kb]) ? ka : kb;
  auto cross2 = [](double ax, double ay, double bx, double by, double cx, double cy) {
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  };
  if (!(X(ring[pk]) == hit && Y(ring[pk]) == my)) {
    const double px = X(ring[pk]), py = Y(ring[pk]);
    double best_tan = INFINITY, best_d = INFINITY;
    size_t best = SIZE_MAX;
    for (size_t j = 0; j < n; ++j) {
      const uint32_t r = ring[j];
      if (r == ring[pk]) continue;
      const uint32_t a = ring[(j + n - 1) % n], c = ring[(j + 1) % n];
      if (cross2(X(a), Y(a), X(r), Y(r), X(c), Y(c)) > 0) continue;  // convex corners hide nothing
      const double rx = X(r), ry = Y(r);
      const double d1 = cross2(mx, my, hit, my, rx, ry), d2 = cross2(hit, my, px, py, rx, ry),
                   d3 = cross2(px, py, mx, my, rx, ry);
      const bool neg = d1 < 0 || d2 < 0 || d3 < 0, pos = d1 > 0 || d2 > 0 || d3 > 0;
      if (neg && pos) continue;  // outside the triangle
      const double t = rx > mx ? std::fabs(ry - my) / (rx - mx) : INFINITY;
      const double d = (rx - mx) * (rx - mx) + (ry - my) * (ry - my);
      if (best == SIZE_MAX || t < best_tan || (t == best_tan && d < best_d)) best = j, best_tan = t, best_d = d;
    }
    if (best != SIZE_MAX) pk = best;
  }
  // P may be in the ring more than once (an earlier bridge ends there): take
  // the occurrence whose inside wedge holds the direction to M.
  const uint32_t p = ring[pk];
  auto in_wedge = [&](size_t at) {  // M seen from P at ring[at] is inside the polygon's corner there
    const uint32_t pa = ring[(at + n - 1) % n], pc = ring[(at + 1) % n];
    const double ux = X(pc) - X(p), uy = Y(pc) - Y(p), vx = X(pa) - X(p), vy = Y(pa) - Y(p);
    const double dx = mx - X(p), dy = my - Y(p);
    const double ud = ux * dy - uy * dx, dv = dx * vy - dy * vx;
    return cross2(X(pa), Y(pa), X(p), Y(p), X(pc), Y(pc)) > 0 ? ud > 0 && dv > 0 : ud > 0 || dv > 0;
  };
  for (size_t k = 0; k < n; ++k) {
    if (ring[k] != p || k == pk) continue;
    if (!in_wedge(pk) && in_wedge(k)) {
      pk = k;
      break;
    }
  }
  std::vector<uint32_t> joined;
  joined.reserve(n + h + 2);
  joined.insert(joined.end(), ring.begin(), ring.begin() + long(pk) + 1);
  for (size_t t = 0; t <= h; ++t) joined.push_back(hole[(mi + t) % h]);
  joined.push_back(p);
  joined.insert(joined.end(), ring.begin() + long(pk) + 1, ring.end());
  ring.swap(joined);
  return true;
}

// Triangulates a polygon with holes (rings of indices into pos, the first the
// outer one; every ring at least 3 corners): holes are turned against the
// outer ring, bridged into it from right to left and the one ring is ear
// clipped in the outer ring's plane. Counts the polygon in
// polygons_holes_failed when its triangles do not cover exactly the outer
// area minus the holes' (a hole outside its ring or overlapping another,
// self-intersecting rings), and in polygons_fanned as triangulate() does.
void triangulate_with_holes(const std::vector<double>& pos, std::vector<std::vector<uint32_t>> rings,
                            std::vector<uint32_t>& out, LoadReport& rep) {
  const std::array<double, 3> nrm = newell(pos, rings[0]);
  const Plane2 pl = plane_of(nrm);
  auto X = [&](uint32_t i) { return pos[3 * size_t(i) + pl.ax]; };
  auto Y = [&](uint32_t i) { return pos[3 * size_t(i) + pl.ay] * pl.s; };
  // Twice the signed area, relative to the ring's first corner (UTM-sized
  // coordinates would otherwise cancel digits).
  auto area2 = [&](const std::vector<uint32_t>& r) {
    double a = 0;
    const double ox = X(r[0]), oy = Y(r[0]);
    for (size_t i = 0; i < r.size(); ++i) {
      const uint32_t p = r[i], q = r[(i + 1) % r.size()];
      a += (X(p) - ox) * (Y(q) - oy) - (Y(p) - oy) * (X(q) - ox);
    }
    return a;
  };
  const double outer = area2(rings[0]);
  double expected = outer;
  std::vector<std::pair<double, size_t>> order;  // holes by rightmost x, right first
  for (size_t k = 1; k < rings.size(); ++k) {
    double a = area2(rings[k]);
    if (a > 0) std::reverse(rings[k].begin(), rings[k].end()), a = -a;
    expected += a;
    double right = -INFINITY;
    for (uint32_t i : rings[k]) right = std::max(right, X(i));
    order.push_back({right, k});
  }
  std::sort(order.begin(), order.end(), [](auto& a, auto& b) { return a.first > b.first; });
  std::vector<uint32_t> ring = rings[0];
  bool bridged = outer > 0;  // a ring that does not face its own normal cannot hold holes
  for (auto& [right, k] : order) bridged &= bridge_hole(ring, rings[k], X, Y);
  const size_t before = out.size();
  rep.polygons_fanned += triangulate(pos, ring, out, &nrm);
  double got = 0;
  for (size_t t = before; t < out.size(); t += 3) got += std::fabs(area2({out[t], out[t + 1], out[t + 2]}));
  if (!bridged || !(std::fabs(got - expected) <= 1e-6 * std::fabs(outer))) ++rep.polygons_holes_failed;
}

// ---------------------------------------------------------------- CityJSON

using Json = nlohmann::json;

Json parse_json(const std::string& path, const std::string& text) {
  try {
    return Json::parse(text);
  } catch (const Json::exception& e) {
    fail(path, std::string("malformed JSON: ") + e.what());
  }
}

// A member that is a string, else "" (nlohmann's value() throws on other types).
std::string text_of(const Json& j, const char* key) {
  if (!j.is_object()) return {};
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

std::string json_excerpt(const Json& j) {
  std::string d = j.dump();
  return d.size() > 40 ? d.substr(0, 37) + "..." : d;
}

// A file without an extension (and not OBJ) is read as CityJSON when it is a
// JSON object whose "type" is "CityJSON".
bool looks_like_cityjson(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  char c = 0;
  while (f.get(c) && std::isspace(static_cast<unsigned char>(c))) {
  }
  if (c != '{') return false;
  std::ostringstream ss;
  f.seekg(0);
  ss << f.rdbuf();
  Json doc = Json::parse(ss.str(), nullptr, false);
  return doc.is_object() && doc.value("type", Json()) == "CityJSON";
}

// A LOD as a number: CityJSON 1.1/2.0 write strings ("2.2"), 1.0 numbers.
bool lod_number(const Json& j, double& v) {
  if (j.is_number()) return v = j.get<double>(), std::isfinite(v);
  if (!j.is_string()) return false;
  const std::string& s = j.get_ref<const std::string&>();
  return !s.empty() && parse_double(s, v) && std::isfinite(v);
}

// The colour of a semantic surface type where no material gives one.
bool semantic_color(const std::string& type, std::array<float, 3>& c) {
  static const std::map<std::string, std::array<float, 3>> kColors = {
      {"RoofSurface", {0.75f, 0.28f, 0.22f}},   {"WallSurface", {0.85f, 0.85f, 0.82f}},
      {"GroundSurface", {0.25f, 0.25f, 0.25f}}, {"ClosureSurface", {0.6f, 0.6f, 0.6f}},
      {"OuterCeilingSurface", {0.7f, 0.7f, 0.7f}}, {"OuterFloorSurface", {0.45f, 0.45f, 0.45f}},
      {"Window", {0.45f, 0.6f, 0.8f}},          {"Door", {0.5f, 0.35f, 0.2f}},
  };
  auto it = kColors.find(type);
  if (it == kColors.end()) return false;
  c = it->second;
  return true;
}

class CityJsonReader {
 public:
  CityJsonReader(const std::string& path, const Json& doc, const LoadOptions& opt, LoadReport& rep)
      : path_(path), doc_(doc), opt_(opt), rep_(rep) {}

  RawModel read() {
    const std::string type = doc_.is_object() ? text_of(doc_, "type") : std::string();
    if (type != "CityJSON")
      fail(path_, "not a CityJSON file (its top-level \"type\" is " +
                      (doc_.is_object() && doc_.contains("type") ? json_excerpt(doc_["type"]) : std::string("missing")) +
                      ", not \"CityJSON\"); perclod reads .json files as CityJSON only");
    read_vertices();
    read_templates();
    const Json* objects = member(doc_, "CityObjects");
    if (!objects || !objects->is_object()) fail(path_, "no \"CityObjects\" object");
    objects_ = objects;
    double wanted = 0;
    const bool any_lod = opt_.cityjson_lod.empty();
    if (!any_lod && !parse_double(opt_.cityjson_lod, wanted))
      fail(path_, "CityJSON LOD '" + opt_.cityjson_lod + "' is not a number (e.g. 2, 2.2, 3; \"\" for the highest)");

    // Pass 1: each object's geometries at the chosen LOD, and its ancestry.
    struct Picked {
      std::vector<std::string> chain;  // ids, top-level first
      std::vector<const Json*> geometries;
      std::string name;
    };
    std::vector<Picked> picked;
    std::map<std::string, bool> top_has_child_geometry;
    for (auto it = objects->begin(); it != objects->end(); ++it) {
      const std::string& id = it.key();
      const Json& obj = it.value();
      if (!obj.is_object()) fail(path_, "CityObject '" + id + "' is not a JSON object");
      const Json* geoms = member(obj, "geometry");
      if (!geoms || geoms->is_null()) continue;
      if (!geoms->is_array()) fail(path_, "CityObject '" + id + "': \"geometry\" is not an array");
      std::vector<std::pair<double, const Json*>> usable;
      for (size_t g = 0; g < geoms->size(); ++g) {
        where_ = "CityObject '" + id + "' geometry " + std::to_string(g);
        const Json& geom = (*geoms)[g];
        if (!geom.is_object()) fail(path_, where_ + " is not a JSON object");
        const Json& shape = geometry_shape(geom);
        if (surface_depth(text_of(shape, "type")) < 0) {
          ++rep_.cityjson_geometries_unsupported;
          continue;
        }
        double lod = 0;
        if (!lod_number(shape.value("lod", Json()), lod))
          fail(path_, where_ + ": \"lod\" is missing or not a number (" + json_excerpt(shape.value("lod", Json())) + ")");
        usable.push_back({lod, &geom});
      }
      if (usable.empty()) continue;
      double pick = wanted;
      if (any_lod)
        for (auto& u : usable) pick = std::max(pick, u.first);
      Picked p;
      for (auto& u : usable)
        if (u.first == pick) p.geometries.push_back(u.second);
      if (p.geometries.empty()) {
        ++rep_.cityjson_objects_without_lod;
        continue;
      }
      p.chain = ancestry(id);
      if (p.chain.size() > 1) top_has_child_geometry[p.chain[0]] = true;
      picked.push_back(std::move(p));
    }
    // Names: "<top>/<child>", so find_buildings() groups a building's parts.
    for (auto& p : picked) {
      for (size_t k = 0; k < p.chain.size(); ++k) p.name += (k ? "/" : "") + clean_id(p.chain[k]);
      if (p.chain.size() == 1 && top_has_child_geometry.count(p.chain[0])) p.name += "/" + clean_id(p.chain[0]);
    }
    std::stable_sort(picked.begin(), picked.end(), [](const Picked& a, const Picked& b) { return a.name < b.name; });

    // Pass 2: the surfaces.
    for (auto& p : picked) {
      auto [it, added] = component_ids_.try_emplace(p.name, uint32_t(m_.component_names.size()));
      if (added) m_.component_names.push_back(p.name);
      const uint32_t comp = it->second;
      const Json& geoms = (*objects_)[p.chain.back()]["geometry"];
      for (const Json* g : p.geometries) {
        const size_t gi = size_t(g - &geoms[0]);
        where_ = "CityObject '" + p.chain.back() + "' geometry " + std::to_string(gi);
        emit_geometry(*g, comp);
      }
    }
    if (m_.indices.empty() && rep_.cityjson_objects_without_lod)
      fail(path_, "no CityObject has geometry at LOD " + opt_.cityjson_lod + " (" +
                      std::to_string(rep_.cityjson_objects_without_lod) + " have other LODs only)");
    m_.objects_are_components = true;
    return std::move(m_);
  }

 private:
  // A vertex list to read ring indices from: the file's (already through
  // its transform) or a template's (placed by an instance's matrix + anchor).
  struct VertexSource {
    const std::vector<double>* xyz = nullptr;
    const double* matrix = nullptr;  // 4x4 row-major, nullptr = identity
    double anchor[3] = {0, 0, 0};
    std::vector<uint32_t> remap;     // source vertex -> RawModel vertex, UINT32_MAX = not yet
    const char* what = "vertex";
    const char* plural = "vertices";
  };

  static const Json* member(const Json& j, const char* key) {
    if (!j.is_object()) return nullptr;
    auto it = j.find(key);
    return it == j.end() ? nullptr : &*it;
  }

  static std::string clean_id(std::string id) {
    std::replace(id.begin(), id.end(), '/', '|');  // '/' separates building and part in component names
    return id;
  }

  // Surface nesting below "boundaries": 0 for surfaces, 1 for a Solid's shells,
  // 2 for solids; -1 for geometry without surfaces.
  static int surface_depth(const std::string& type) {
    if (type == "MultiSurface" || type == "CompositeSurface") return 0;
    if (type == "Solid") return 1;
    if (type == "MultiSolid" || type == "CompositeSolid") return 2;
    return -1;
  }

  // The geometry that holds the surfaces: a GeometryInstance's template.
  const Json& geometry_shape(const Json& geom) {
    if (text_of(geom, "type") != "GeometryInstance") return geom;
    const Json* t = member(geom, "template");
    if (!t || !t->is_number_integer()) fail(path_, where_ + ": GeometryInstance without a \"template\" index");
    const long long k = t->get<long long>();
    if (!templates_ || k < 0 || k >= (long long)templates_->size())
      fail(path_, where_ + ": template " + std::to_string(k) + " out of range (" +
                      std::to_string(templates_ ? templates_->size() : 0) + " geometry templates)");
    const Json& shape = (*templates_)[size_t(k)];
    if (!shape.is_object() || text_of(shape, "type") == "GeometryInstance")
      fail(path_, where_ + ": template " + std::to_string(k) + " is not a geometry");
    return shape;
  }

  std::vector<double> read_points(const Json& list, const std::array<double, 3>& scale,
                                  const std::array<double, 3>& translate, const std::string& what) {
    std::vector<double> xyz;
    xyz.reserve(3 * list.size());
    for (size_t i = 0; i < list.size(); ++i) {
      const Json& v = list[i];
      if (!v.is_array() || v.size() != 3)
        fail(path_, what + " " + std::to_string(i) + " is " + json_excerpt(v) + ", not 3 numbers");
      for (int a = 0; a < 3; ++a) {
        if (!v[a].is_number())
          fail(path_, what + " " + std::to_string(i) + " coordinate " + std::to_string(a) + " is " +
                          json_excerpt(v[a]) + ", not a number");
        const double x = v[a].get<double>() * scale[a] + translate[a];
        if (!std::isfinite(x)) fail(path_, what + " " + std::to_string(i) + " coordinate is NaN/inf");
        xyz.push_back(x);
      }
    }
    return xyz;
  }

  void read_vertices() {
    std::array<double, 3> scale{1, 1, 1}, translate{0, 0, 0};
    if (const Json* t = member(doc_, "transform")) {
      for (auto [key, out] : {std::pair{"scale", &scale}, std::pair{"translate", &translate}}) {
        const Json* v = member(*t, key);
        bool ok = v && v->is_array() && v->size() == 3;
        for (int a = 0; ok && a < 3; ++a) {
          ok = (*v)[a].is_number() && std::isfinite((*out)[a] = (*v)[a].get<double>());
        }
        if (!ok) fail(path_, std::string("\"transform\" needs \"") + key + "\": 3 numbers");
      }
    }
    const Json* v = member(doc_, "vertices");
    if (!v || !v->is_array()) fail(path_, "no \"vertices\" array");
    vertices_ = read_points(*v, scale, translate, "vertex");
  }

  void read_templates() {
    const Json* gt = member(doc_, "geometry-templates");
    if (!gt) return;
    templates_ = member(*gt, "templates");
    if (templates_ && !templates_->is_array()) fail(path_, "\"geometry-templates\".\"templates\" is not an array");
    const Json* tv = member(*gt, "vertices-templates");
    if (tv && !tv->is_array()) fail(path_, "\"geometry-templates\".\"vertices-templates\" is not an array");
    // Template vertices are not quantised: no transform.
    if (tv) template_vertices_ = read_points(*tv, {1, 1, 1}, {0, 0, 0}, "template vertex");
  }

  // The ids from the top-level object down to `id`, following first parents.
  std::vector<std::string> ancestry(const std::string& id) {
    std::vector<std::string> chain{id};
    for (;;) {
      const Json& obj = (*objects_)[chain.back()];
      const Json* parents = member(obj, "parents");
      if (!parents || parents->is_null() || (parents->is_array() && parents->empty())) break;
      if (!parents->is_array() || !(*parents)[0].is_string())
        fail(path_, "CityObject '" + chain.back() + "': \"parents\" is not an array of ids");
      const std::string& parent = (*parents)[0].get_ref<const std::string&>();
      if (!objects_->contains(parent))
        fail(path_, "CityObject '" + chain.back() + "': parent '" + parent + "' is not in CityObjects");
      if (std::find(chain.begin(), chain.end(), parent) != chain.end())
        fail(path_, "CityObject '" + id + "': its parents form a cycle (through '" + parent + "')");
      chain.push_back(parent);
    }
    std::reverse(chain.begin(), chain.end());
    return chain;
  }

  uint32_t vertex(VertexSource& src, const Json& idx) {
    const size_t n = src.xyz->size() / 3;
    if (!idx.is_number_integer())
      fail(path_, where_ + ": ring entry " + json_excerpt(idx) + " is not a vertex index");
    const long long i = idx.get<long long>();
    if (i < 0 || (unsigned long long)i >= n || (idx.is_number_unsigned() && idx.get<unsigned long long>() >= n))
      fail(path_, where_ + ": " + src.what + " index " + idx.dump() + " out of range (" + std::to_string(n) + " " +
                      src.plural + ")");
    uint32_t& r = src.remap[size_t(i)];
    if (r == UINT32_MAX) {
      r = uint32_t(m_.positions.size() / 3);
      const double* p = &(*src.xyz)[3 * size_t(i)];
      for (int a = 0; a < 3; ++a) {
        double v = p[a];
        if (src.matrix) {
          const double* row = src.matrix + 4 * a;
          v = row[0] * p[0] + row[1] * p[1] + row[2] * p[2] + row[3];
        }
        m_.positions.push_back(v + src.anchor[a]);
      }
    }
    return r;
  }

  uint32_t material(const std::string& key, const Material& mat) {
    auto [it, added] = material_ids_.try_emplace(key, uint32_t(m_.materials.size()));
    if (added) m_.materials.push_back(mat);
    return it->second;
  }

  // The scene material of a surface: its appearance material, else its
  // semantic type's colour, else the default.
  uint32_t surface_material(const Json* sem_value, const Json* mat_value, const Json* sem_surfaces) {
    const Json* appearance_materials = nullptr;
    if (const Json* app = member(doc_, "appearance")) appearance_materials = member(*app, "materials");
    if (mat_value && mat_value->is_number_integer() && appearance_materials && appearance_materials->is_array()) {
      const long long k = mat_value->get<long long>();
      if (k >= 0 && k < (long long)appearance_materials->size()) {
        const Json& am = (*appearance_materials)[size_t(k)];
        Material mt;
        mt.name = am.is_object() && am.value("name", Json()).is_string() ? am["name"].get<std::string>()
                                                                         : "material" + std::to_string(k);
        const Json* dc = member(am, "diffuseColor");
        if (dc && dc->is_array() && dc->size() == 3 && (*dc)[0].is_number() && (*dc)[1].is_number() &&
            (*dc)[2].is_number()) {
          for (int a = 0; a < 3; ++a) mt.color[a] = std::clamp((*dc)[a].get<float>(), 0.0f, 1.0f);
          mt.has_color = true;
        }
        return material("material:" + std::to_string(k), mt);
      }
    }
    if (sem_value && sem_value->is_number_integer() && sem_surfaces && sem_surfaces->is_array()) {
      const long long k = sem_value->get<long long>();
      if (k >= 0 && k < (long long)sem_surfaces->size()) {
        const std::string type = text_of((*sem_surfaces)[size_t(k)], "type");
        Material mt;
        mt.name = type;
        if (semantic_color(type, mt.color)) {
          mt.has_color = true;
          return material("semantic:" + type, mt);
        }
      }
    }
    return material("default", {"default", {0.8f, 0.8f, 0.8f}, false});
  }

  void emit_geometry(const Json& geom, uint32_t comp) {
    const Json& shape = geometry_shape(geom);
    VertexSource src;
    std::array<double, 16> matrix{};
    if (&shape != &geom) {  // a GeometryInstance: template vertices, its matrix, its anchor
      const Json* b = member(geom, "boundaries");
      if (!b || !b->is_array() || b->size() != 1)
        fail(path_, where_ + ": a GeometryInstance's \"boundaries\" must hold one vertex (its anchor)");
      const Json& idx = (*b)[0];
      if (!idx.is_number_integer() || idx.get<long long>() < 0 ||
          idx.get<unsigned long long>() >= vertices_.size() / 3)
        fail(path_, where_ + ": anchor vertex index " + json_excerpt(idx) + " out of range (" +
                        std::to_string(vertices_.size() / 3) + " vertices)");
      for (int a = 0; a < 3; ++a) src.anchor[a] = vertices_[3 * idx.get<size_t>() + a];
      const Json* mj = member(geom, "transformationMatrix");
      bool ok = mj && mj->is_array() && mj->size() == 16;
      for (size_t k = 0; ok && k < 16; ++k)
        ok = (*mj)[k].is_number() && std::isfinite(matrix[k] = (*mj)[k].get<double>());
      if (!ok) fail(path_, where_ + ": a GeometryInstance needs a \"transformationMatrix\" of 16 numbers");
      src.matrix = matrix.data();
      src.xyz = &template_vertices_;
      src.what = "template vertex";
      src.plural = "template vertices";
      src.remap.assign(template_vertices_.size() / 3, UINT32_MAX);
    } else {
      src.xyz = &vertices_;
      if (file_remap_.empty()) file_remap_.assign(vertices_.size() / 3, UINT32_MAX);
      src.remap.swap(file_remap_);  // shared by every non-instance geometry; swapped back below
    }
    const int depth = surface_depth(text_of(shape, "type"));
    const Json* boundaries = member(shape, "boundaries");
    if (!boundaries) fail(path_, where_ + ": no \"boundaries\"");
    const Json* sem = member(shape, "semantics");
    const Json* sem_values = sem ? member(*sem, "values") : nullptr;
    const Json* sem_surfaces = sem ? member(*sem, "surfaces") : nullptr;
    const Json* mat_values = nullptr;
    const Json* mat_value = nullptr;
    if (const Json* mats = member(shape, "material"); mats && mats->is_object() && !mats->empty()) {
      const Json* theme = &mats->begin().value();
      if (const Json* app = member(doc_, "appearance"))
        if (const Json* dt = member(*app, "default-theme-material"); dt && dt->is_string())
          if (const Json* t = member(*mats, dt->get_ref<const std::string&>().c_str())) theme = t;
      mat_values = member(*theme, "values");
      mat_value = member(*theme, "value");
    }
    walk(*boundaries, depth, sem_values, mat_values ? mat_values : nullptr, mat_value, sem_surfaces, comp, src);
    if (&shape == &geom) src.remap.swap(file_remap_);
  }

  static const Json* child(const Json* j, size_t i) {
    return j && j->is_array() && i < j->size() ? &(*j)[i] : nullptr;
  }

  void walk(const Json& b, int depth, const Json* sem, const Json* mat, const Json* mat_value,
            const Json* sem_surfaces, uint32_t comp, VertexSource& src) {
    if (!b.is_array()) fail(path_, where_ + ": \"boundaries\" are not nested arrays as its type needs");
    for (size_t i = 0; i < b.size(); ++i) {
      if (depth > 0) {
        walk(b[i], depth - 1, child(sem, i), child(mat, i), mat_value, sem_surfaces, comp, src);
        continue;
      }
      const Json* mv = child(mat, i);
      surface(b[i], surface_material(child(sem, i), mv && !mv->is_null() ? mv : mat_value, sem_surfaces), comp, src);
    }
  }

  void surface(const Json& s, uint32_t mat, uint32_t comp, VertexSource& src) {
    if (!s.is_array() || s.empty() || !s[0].is_array())
      fail(path_, where_ + ": a surface must be an array of rings (arrays of vertex indices), not " + json_excerpt(s));
    ++rep_.polygons;
    std::vector<std::vector<uint32_t>> rings;
    for (const Json& ring : s) {
      if (!ring.is_array()) fail(path_, where_ + ": a ring must be an array of vertex indices, not " + json_excerpt(ring));
      std::vector<uint32_t> r;
      for (const Json& idx : ring) {
        const uint32_t v = vertex(src, idx);
        if (r.empty() || r.back() != v) r.push_back(v);  // repeated corners add nothing
      }
      while (r.size() > 1 && r.back() == r.front()) r.pop_back();  // a closed ring repeats its first corner
      // Holes of fewer than 3 corners have no area to cut.
      if (rings.empty() || r.size() >= 3) rings.push_back(std::move(r));
    }
    if (rings[0].size() < 3) {
      ++rep_.polygons_skipped;
      return;
    }
    const size_t before = m_.indices.size();
    if (rings[0].size() > 3 || rings.size() > 1) ++rep_.polygons_triangulated;
    if (rings.size() == 1) {
      rep_.polygons_fanned += triangulate(m_.positions, rings[0], m_.indices);
    } else {
      ++rep_.polygons_with_holes;
      triangulate_with_holes(m_.positions, std::move(rings), m_.indices, rep_);
    }
    for (size_t t = before / 3; t < m_.indices.size() / 3; ++t) {
      m_.component.push_back(comp);
      m_.material.push_back(mat);
    }
  }

  const std::string& path_;
  const Json& doc_;
  const LoadOptions& opt_;
  LoadReport& rep_;
  const Json* objects_ = nullptr;
  const Json* templates_ = nullptr;
  std::vector<double> vertices_, template_vertices_;
  std::vector<uint32_t> file_remap_;
  std::string where_;
  RawModel m_;
  std::map<std::string, uint32_t> component_ids_, material_ids_;
};

RawModel read_cityjson(const std::string& path, const LoadOptions& opt, LoadReport& rep) {
  const Json doc = parse_json(path, read_file(path));
  try {
    return CityJsonReader(path, doc, opt, rep).read();
  } catch (const Json::exception& e) {  // a member of an unexpected type the checks above missed
    fail(path, std::string("malformed CityJSON: ") + e.what());
  }
}

// ---------------------------------------------------------------- assimp

void assimp_node(const aiScene* sc, const aiNode* node, const aiMatrix4x4& parent, RawModel& m,
                 LoadReport& rep, const std::string& path) {
  aiMatrix4x4 xf = parent * node->mTransformation;
  for (unsigned k = 0; k < node->mNumMeshes; ++k) {
    const aiMesh* mesh = sc->mMeshes[node->mMeshes[k]];
    std::string name = node->mName.length ? node->mName.C_Str() : mesh->mName.C_Str();
    if (name.empty()) name = "mesh" + std::to_string(node->mMeshes[k]);
    uint32_t comp = uint32_t(m.component_names.size());
    m.component_names.push_back(name);
    uint32_t base = uint32_t(m.positions.size() / 3);
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      aiVector3D p = xf * mesh->mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fail(path, "mesh '" + name + "' vertex " + std::to_string(v) + " is NaN/inf");
      m.positions.insert(m.positions.end(), {double(p.x), double(p.y), double(p.z)});
    }
    std::vector<uint32_t> poly;
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      ++rep.polygons;
      if (face.mNumIndices < 3)
        fail(path, "mesh '" + name + "' has point or line primitives (" +
                       std::to_string(face.mNumIndices) + " corners); perclod needs surfaces");
      poly.assign(face.mIndices, face.mIndices + face.mNumIndices);
      for (auto& i : poly) {
        if (i >= mesh->mNumVertices) fail(path, "mesh '" + name + "' face index out of range");
        i += base;
      }
      if (poly.size() > 3) ++rep.polygons_triangulated;
      size_t before = m.indices.size();
      rep.polygons_fanned += triangulate(m.positions, poly, m.indices);
      for (size_t t = before / 3; t < m.indices.size() / 3; ++t) {
        m.component.push_back(comp);
        m.material.push_back(mesh->mMaterialIndex);
      }
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) assimp_node(sc, node->mChildren[c], xf, m, rep, path);
}

// Checks made before assimp sees a file: assimp trusts declared sizes (a PLY
// declaring 1e8 vertices in 108 bytes read for minutes) and tries every
// reader on a file its own reader refuses (a GLB with a corrupt chunk length
// took 47 s to be rejected).

// Bytes one PLY property takes in a binary file, 0 for an unknown type.
size_t ply_type_size(std::string_view t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

// A PLY header's element counts must fit in the bytes after it: at least the
// fixed-size properties (and list counts) per element in binary, at least two
// bytes ("0 ") per value in ASCII.
void check_ply(const std::string& path, const std::string& data) {
  // The header is every line up to the first that is exactly "end_header"
  // (assimp took "2.0atend_header" for the end and then never returned).
  size_t end = std::string::npos, body = 0;  // where the end_header line starts, and the data after it
  for (size_t at = 0; at < data.size();) {
    size_t nl = data.find('\n', at);
    size_t stop = nl == std::string::npos ? data.size() : nl;
    std::string_view l(data.data() + at, stop - at);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    if (l == "end_header") {
      end = at;
      body = nl == std::string::npos ? data.size() : nl + 1;
      break;
    }
    if (nl == std::string::npos) break;
    at = nl + 1;
  }
  if (end == std::string::npos)
    fail(path, "PLY file without an 'end_header' line (truncated or not a PLY file)");
  const double available = double(data.size() - body);
  std::istringstream header(data.substr(0, end));
  std::string line, format;
  struct Element {
    std::string name;
    double count = 0, min_bytes = 0;
  };
  std::vector<Element> elements;
  // The header is checked line by line before assimp sees it: assimp's PLY
  // reader looped forever on a garbled header line (fuzz finding
  // tests/fuzz/findings/fuzz_assimp/timeout-ply-header-hang-2.ply).
  int line_no = 0;
  auto bad_line = [&](const std::string& why) {
    fail(path, "PLY header line " + std::to_string(line_no) + ": " + why);
  };
  while (std::getline(header, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    for (unsigned char c : line)
      if (c < 0x20 && c != '\t') bad_line("control character in the header (corrupt)");
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (line_no == 1) {
      if (key != "ply") bad_line("expected 'ply'");
      continue;
    }
    if (key == "comment" || key == "obj_info") continue;
    if (key != "format" && key != "element" && key != "property")
      bad_line("'" + key.substr(0, 40) + "' is not a PLY header keyword (format, element, property, comment)");
    for (unsigned char c : line)
      if (c >= 0x80) bad_line("non-ASCII byte in a '" + key + "' line (corrupt)");
    if (key == "format") {
      ls >> format;
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        bad_line("unknown format '" + format.substr(0, 40) + "'");
    } else if (key == "element") {
      Element e;
      std::string count;
      ls >> e.name >> count;
      unsigned long long n = 0;
      auto r = std::from_chars(count.data(), count.data() + count.size(), n);
      if (r.ec != std::errc() || r.ptr != count.data() + count.size())
        fail(path, "PLY header: element '" + e.name + "' count '" + count + "' is not a number");
      e.count = double(n);
      elements.push_back(e);
    } else {  // property
      if (elements.empty()) bad_line("property before any element");
      std::string type, item, name;
      ls >> type;
      if (type == "list") {
        ls >> type >> item;  // the count's type (an empty list still holds it), the items' type
        if (!ply_type_size(item)) bad_line("unknown list item type '" + item.substr(0, 40) + "'");
      }
      if (!ply_type_size(type)) bad_line("unknown property type '" + type.substr(0, 40) + "'");
      if (!(ls >> name)) bad_line("property without a name");
      elements.back().min_bytes += format == "ascii" ? 2 : double(ply_type_size(type));
    }
  }
  double needed = 0;
  const Element* largest = nullptr;
  for (const auto& e : elements) {
    needed += e.count * e.min_bytes;
    if (!largest || e.count * e.min_bytes > largest->count * largest->min_bytes) largest = &e;
  }
  if (needed > available + 1)  // +1: the last ASCII value needs no separator
    fail(path, "PLY header declares " + std::to_string((unsigned long long)largest->count) + " " + largest->name +
                   " elements, which need at least " + std::to_string((unsigned long long)needed) +
                   " bytes, but the file holds only " + std::to_string((unsigned long long)available) +
                   " bytes after its header (truncated or corrupt)");
}

uint32_t le32(const std::string& d, size_t at) {
  return uint32_t(uint8_t(d[at])) | uint32_t(uint8_t(d[at + 1])) << 8 | uint32_t(uint8_t(d[at + 2])) << 16 |
         uint32_t(uint8_t(d[at + 3])) << 24;
}

// A GLB's header length and chunk lengths must match the file.
void check_glb(const std::string& path, const std::string& d) {
  if (d.size() < 20) fail(path, "GLB file too short for its header (" + std::to_string(d.size()) + " bytes)");
  const uint64_t total = le32(d, 8);
  if (total > d.size())
    fail(path, "GLB header says " + std::to_string(total) + " bytes but the file has only " +
                   std::to_string(d.size()) + " (truncated or corrupt)");
  uint64_t at = 12;
  for (int chunk = 0; at < total; ++chunk) {
    if (at + 8 > total) fail(path, "GLB chunk " + std::to_string(chunk) + " header is cut off (corrupt)");
    const uint64_t len = le32(d, size_t(at));
    if (at + 8 + len > total)
      fail(path, "GLB chunk " + std::to_string(chunk) + " declares " + std::to_string(len) + " bytes but only " +
                     std::to_string(total - at - 8) + " follow (truncated or corrupt)");
    if (chunk == 0 && le32(d, size_t(at) + 4) != 0x4E4F534Au) fail(path, "GLB's first chunk is not JSON (corrupt)");
    at += 8 + len;
  }
}

RawModel read_assimp(const std::string& path, LoadReport& rep) {
  const std::string data = read_file(path);  // same existence / readability errors as OBJ
  // Files that claim a format by their magic or their extension: assimp picks
  // its reader by either (a PLY starting "ply?" hung it as well).
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (data.compare(0, 3, "ply") == 0 || ext == ".ply") check_ply(path, data);
  if (data.compare(0, 4, "glTF") == 0 || ext == ".glb") check_glb(path, data);
  // No aiProcess_Triangulate: perclod triangulates, so it can count polygons.
  // aiProcess_ValidateDataStructure runs before the other steps: without it a
  // truncated binary PLY's out-of-range face indices crashed JoinIdenticalVertices.
  const aiScene* sc = aiImportFile(path.c_str(), aiProcess_ValidateDataStructure | aiProcess_JoinIdenticalVertices);
  if (!sc || !sc->mRootNode) fail(path, std::string("cannot parse: ") + aiGetErrorString());
  RawModel m;
  for (unsigned i = 0; i < sc->mNumMaterials; ++i) {
    Material mt;
    aiString nm;
    if (sc->mMaterials[i]->Get(AI_MATKEY_NAME, nm) == AI_SUCCESS) mt.name = nm.C_Str();
    aiColor3D c;
    if (sc->mMaterials[i]->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) {
      mt.color = {c.r, c.g, c.b};
      mt.has_color = true;
    }
    m.materials.push_back(mt);
  }
  if (m.materials.empty()) m.materials.push_back({"default", {0.8f, 0.8f, 0.8f}, false});
  try {
    assimp_node(sc, sc->mRootNode, aiMatrix4x4(), m, rep, path);
  } catch (...) {
    aiReleaseImport(sc);
    throw;
  }
  aiReleaseImport(sc);
  return m;
}

// ---------------------------------------------------------------- common

Scene build_scene(RawModel&& m, const std::string& path, const LoadOptions& opt, LoadReport& rep) {
  if (m.indices.empty()) fail(path, "no triangles (empty model)");
  if (!(opt.scale > 0) || !std::isfinite(opt.scale)) fail(path, "unit scale must be a positive number");
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (uint32_t i : m.indices)
    for (int a = 0; a < 3; ++a) {
      double v = m.positions[3 * size_t(i) + a] * opt.scale;
      lo[a] = std::min(lo[a], v);
      hi[a] = std::max(hi[a], v);
    }
  auto num = [](double v) {
    char buf[32];
    return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
  };
  const std::string scale_note = opt.scale == 1 ? "" : " (times unit scale " + num(opt.scale) + ")";
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]))
      fail(path, "coordinates overflow" + scale_note + ": the model is too large or the unit scale is wrong");
  Scene s;
  for (int a = 0; a < 3; ++a) s.offset[a] = 0.5 * (lo[a] + hi[a]);
  s.positions.resize(m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const double v = m.positions[i] * opt.scale - s.offset[i % 3];
    // Positions are float after recentring: a coordinate beyond float's range
    // (about 3.4e38) would become infinite.
    if (!(std::fabs(v) <= double(std::numeric_limits<float>::max())))
      fail(path, "vertex " + std::to_string(i / 3 + 1) + " coordinate " + num(m.positions[i]) + scale_note +
                     " is too far from the model's centre for float precision (beyond 3.4e38): the model is "
                     "too large or the unit scale is wrong");
    s.positions[i] = float(v);
  }
  s.indices = std::move(m.indices);
  s.material = std::move(m.material);
  s.materials = std::move(m.materials);
  // Components: the file's groups, or connectivity where it has at most one.
  if (m.component_names.size() <= 1 && !m.objects_are_components) {
    uint32_t n = connected_parts(s, s.component);
    s.component_names.resize(n);
    for (uint32_t c = 0; c < n; ++c) s.component_names[c] = "part" + std::to_string(c);
    rep.components_from_connectivity = true;
  } else {
    s.component = std::move(m.component);
    s.component_names = std::move(m.component_names);
  }
  for (size_t t = 0; t < s.triangle_count(); ++t) rep.degenerate_triangles += is_degenerate(s, t);
  try {
    validate(s);  // e.g. a coordinate that overflows float after recentring and scaling
  } catch (const std::invalid_argument& e) {
    fail(path, e.what());
  }
  return s;
}

}  // namespace

bool is_degenerate(const Scene& s, size_t t) {
  uint32_t a = s.indices[3 * t], b = s.indices[3 * t + 1], c = s.indices[3 * t + 2];
  if (a == b || b == c || a == c) return true;
  const float* A = &s.positions[3 * size_t(a)];
  const float* B = &s.positions[3 * size_t(b)];
  const float* C = &s.positions[3 * size_t(c)];
  double u[3], v[3];
  for (int k = 0; k < 3; ++k) u[k] = double(B[k]) - A[k], v[k] = double(C[k]) - A[k];
  double cx = u[1] * v[2] - u[2] * v[1], cy = u[2] * v[0] - u[0] * v[2], cz = u[0] * v[1] - u[1] * v[0];
  return cx == 0 && cy == 0 && cz == 0;
}

Scene load_scene(const std::string& path, const LoadOptions& options, LoadReport* report) {
  auto t0 = std::chrono::steady_clock::now();
  LoadReport rep;
  std::string ext = lower_extension(path);
  RawModel raw;
  if (ext == ".obj" || (ext.empty() && looks_like_obj(path))) raw = read_obj(path, rep);
  // .json and .city.json: the content decides (read_cityjson refuses other JSON).
  else if (ext == ".json" || ext == ".cityjson" || (ext.empty() && looks_like_cityjson(path)))
    raw = read_cityjson(path, options, rep);
  else raw = read_assimp(path, rep);
  Scene s = build_scene(std::move(raw), path, options, rep);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (report) *report = rep;
  return s;
}

SceneInfo analyse_scene(const Scene& s) {
  SceneInfo info;
  info.triangles = s.triangle_count();
  info.vertices = s.vertex_count();
  info.components = s.component_count();
  info.materials = s.materials.size();
  info.bounds = scene_bounds(s);
  info.offset = s.offset;
  const std::vector<uint32_t> weld = weld_exact(s);  // per corner
  std::vector<uint64_t> edges;
  edges.reserve(s.indices.size());
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    info.degenerate_triangles += is_degenerate(s, t);
    for (int k = 0; k < 3; ++k) {
      uint64_t a = weld[3 * t + k], b = weld[3 * t + (k + 1) % 3];
      if (a == b) continue;
      edges.push_back(std::min(a, b) << 32 | std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) ++info.boundary_edges;
    if (j - i > 2) ++info.non_manifold_edges;
    i = j;
  }
  return info;
}

nlohmann::json load_report_json(const LoadReport& r) {
  nlohmann::json j = {{"polygons", r.polygons},
                      {"polygons_triangulated", r.polygons_triangulated},
                      {"degenerate_triangles", r.degenerate_triangles},
                      {"components_from_connectivity", r.components_from_connectivity},
                      {"seconds", r.seconds}};
  // Counts of what could not be used as it was: only when it happened.
  for (const auto& [key, n] : {std::pair<const char*, size_t>{"polygons_fanned", r.polygons_fanned},
                               {"polygons_with_holes", r.polygons_with_holes},
                               {"polygons_holes_failed", r.polygons_holes_failed},
                               {"polygons_skipped", r.polygons_skipped},
                               {"cityjson_objects_without_lod", r.cityjson_objects_without_lod},
                               {"cityjson_geometries_unsupported", r.cityjson_geometries_unsupported}})
    if (n) j[key] = n;
  return j;
}

}  // namespace perclod
