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

// Triangulates polygon `poly` (indices into pos) by ear clipping in the plane
// of its Newell normal; falls back to a fan if the polygon is self-intersecting
// (or too costly to clip); returns whether that fallback fanned over 3 corners.
bool triangulate(const std::vector<double>& pos, const std::vector<uint32_t>& poly,
                 std::vector<uint32_t>& out) {
  size_t n = poly.size();
  if (n == 3) {
    out.insert(out.end(), poly.begin(), poly.end());
    return false;
  }
  auto P = [&](uint32_t i, int a) { return pos[3 * size_t(i) + a]; };
  double nx = 0, ny = 0, nz = 0;
  for (size_t i = 0; i < n; ++i) {
    uint32_t a = poly[i], b = poly[(i + 1) % n];
    nx += (P(a, 1) - P(b, 1)) * (P(a, 2) + P(b, 2));
    ny += (P(a, 2) - P(b, 2)) * (P(a, 0) + P(b, 0));
    nz += (P(a, 0) - P(b, 0)) * (P(a, 1) + P(b, 1));
  }
  // Project onto the plane most perpendicular to the normal, keeping orientation.
  int ax = 0, ay = 1;
  double sign = nz;
  if (std::fabs(nx) >= std::fabs(ny) && std::fabs(nx) >= std::fabs(nz)) ax = 1, ay = 2, sign = nx;
  else if (std::fabs(ny) >= std::fabs(nz)) ax = 2, ay = 0, sign = ny;
  double s = sign >= 0 ? 1.0 : -1.0;
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
  if (m.component_names.size() <= 1) {
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
  RawModel raw = ext == ".obj" || (ext.empty() && looks_like_obj(path)) ? read_obj(path, rep) : read_assimp(path, rep);
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
  if (r.polygons_fanned) j["polygons_fanned"] = r.polygons_fanned;  // only when it happened
  return j;
}

}  // namespace perclod
