// OBJ, read by perclod itself in double precision: vertices, faces (any
// corner count, triangulated), groups as components, MTL diffuse colours.
#include "readers.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>


namespace perclod::detail {
namespace fs = std::filesystem;
namespace {

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

}  // namespace

bool parse_double(std::string_view w, double& v) {
  if (!w.empty() && w[0] == '+') w.remove_prefix(1);
  auto r = std::from_chars(w.data(), w.data() + w.size(), v);
  return r.ec == std::errc() && r.ptr == w.data() + w.size();
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

}  // namespace perclod::detail
