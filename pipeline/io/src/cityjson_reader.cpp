// CityJSON 1.0, 1.1 and 2.0: every CityObject with geometry one component,
// vertices through the file's transform in double precision, surfaces with
// holes cut out, colours from materials or semantic surface types.
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

#include <nlohmann/json.hpp>

namespace perclod::detail {
namespace fs = std::filesystem;
namespace {

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

// Appends `j` as JSON to `out` until `out` is longer than `limit`. Each
// array or object level writes a character before its members, so the
// recursion is no deeper than the excerpt is long however deep `j` nests
// (dump() of a vertex nested 100,000 arrays deep overflowed the stack).
void excerpt_into(const Json& j, std::string& out, size_t limit) {
  if (out.size() > limit) return;
  if (!j.is_structured()) {
    out += j.dump();
    return;
  }
  out += j.is_array() ? '[' : '{';
  for (auto it = j.begin(); it != j.end() && out.size() <= limit; ++it) {
    if (it != j.begin()) out += ',';
    if (j.is_object()) out += Json(it.key()).dump() + ':';
    excerpt_into(*it, out, limit);
  }
  out += j.is_array() ? ']' : '}';
}

// At most 40 characters of `j` as JSON, for messages.
std::string json_excerpt(const Json& j) {
  std::string d;
  excerpt_into(j, d, 40);
  return d.size() > 40 ? d.substr(0, 37) + "..." : d;
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
    check_type();
    check_version();
    rep_.reference_system = reference_system();
    read_vertices();
    read_templates();
    const Json* objects = member(doc_, "CityObjects");
    if (!objects || !objects->is_object()) fail(path_, "no \"CityObjects\" object");
    objects_ = objects;
    double wanted = 0;
    const bool any_lod = opt_.cityjson_lod.empty();
    if (!any_lod && !parse_double(opt_.cityjson_lod, wanted))
      fail(path_, "CityJSON LOD '" + opt_.cityjson_lod + "' is not a number (e.g. 2, 2.2, 3; \"\" for the highest)");

    std::map<std::string, bool> top_has_child_geometry;
    std::vector<Picked> picked = pick_objects(wanted, any_lod, top_has_child_geometry);
    name_picked(picked, top_has_child_geometry);
    emit_picked(picked);
    if (m_.indices.empty() && rep_.cityjson_objects_without_lod)
      fail(path_, "no CityObject has geometry at LOD " + opt_.cityjson_lod + " (" +
                      std::to_string(rep_.cityjson_objects_without_lod) + " have other LODs only)");
    m_.objects_are_components = true;
    return std::move(m_);
  }

 private:
  // A CityObject chosen in pass 1: its ancestry, its geometries at the chosen
  // LOD and (once named) its component name.
  struct Picked {
    std::vector<std::string> chain;  // ids, top-level first
    std::vector<const Json*> geometries;
    std::string name;
  };

  // Fails unless the document's top-level "type" is "CityJSON".
  void check_type() const {
    const std::string type = doc_.is_object() ? text_of(doc_, "type") : std::string();
    if (type != "CityJSON")
      fail(path_, "not a CityJSON file (its top-level \"type\" is " +
                      (doc_.is_object() && doc_.contains("type") ? json_excerpt(doc_["type"]) : std::string("missing")) +
                      ", not \"CityJSON\"); perclod reads .json files as CityJSON only");
  }

  // metadata.referenceSystem as written (a string), else its JSON; "" when absent.
  std::string reference_system() const {
    const Json* meta = member(doc_, "metadata");
    const Json* rs = meta ? member(*meta, "referenceSystem") : nullptr;
    if (!rs || rs->is_null()) return {};
    return rs->is_string() ? rs->get<std::string>() : rs->dump();
  }

  // Fails unless "version" is one this reader knows: 1.0, 1.1 or 2.0, with
  // or without a patch number ("1.0.3").
  void check_version() const {
    const Json* v = member(doc_, "version");
    if (!v) fail(path_, "no \"version\" (perclod reads CityJSON 1.0, 1.1 and 2.0)");
    const std::string s = v->is_string() ? v->get<std::string>() : std::string();
    const std::string minor = s.substr(0, 3), patch = s.size() > 3 ? s.substr(3) : std::string();
    const bool known = minor == "1.0" || minor == "1.1" || minor == "2.0";
    const bool patch_ok = patch.empty() || (patch.size() > 1 && patch[0] == '.' &&
                                            patch.find_first_not_of("0123456789", 1) == std::string::npos);
    if (!known || !patch_ok)
      fail(path_, "CityJSON version " + json_excerpt(*v) + " is not supported (perclod reads 1.0, 1.1 and 2.0)");
  }

  // Pass 1: each object's geometries at the chosen LOD, and its ancestry
  // (noting the top-level objects with a child that has geometry).
  std::vector<Picked> pick_objects(double wanted, bool any_lod,
                                   std::map<std::string, bool>& top_has_child_geometry) {
    std::vector<Picked> picked;
    for (auto it = objects_->begin(); it != objects_->end(); ++it) {
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
        const Json* lod_value = member(shape, "lod");  // not shape.value(): no copy of what may nest deep
        if (!lod_value || !lod_number(*lod_value, lod))
          fail(path_, where_ + ": \"lod\" is missing or not a number (" +
                          (lod_value ? json_excerpt(*lod_value) : std::string("null")) + ")");
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
    return picked;
  }

  // Names: "<top>/<child>", so find_buildings() groups a building's parts;
  // then sorted by name.
  static void name_picked(std::vector<Picked>& picked, const std::map<std::string, bool>& top_has_child_geometry) {
    for (auto& p : picked) {
      // Appended piece by piece: GCC 12 warns (-Wrestrict, falsely) on "/" + std::string here.
      for (size_t k = 0; k < p.chain.size(); ++k) {
        if (k) p.name += '/';
        p.name += clean_id(p.chain[k]);
      }
      if (p.chain.size() == 1 && top_has_child_geometry.count(p.chain[0])) {
        p.name += '/';
        p.name += clean_id(p.chain[0]);
      }
    }
    std::stable_sort(picked.begin(), picked.end(), [](const Picked& a, const Picked& b) { return a.name < b.name; });
  }

  // Pass 2: the surfaces of each picked object, as the component of its name.
  void emit_picked(const std::vector<Picked>& picked) {
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
  }

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
      if (!(scale[0] > 0 && scale[1] > 0 && scale[2] > 0))
        fail(path_, "\"transform\" \"scale\" is " + json_excerpt((*t)["scale"]) +
                        ": each must be positive (a zero scale puts every vertex on one point)");
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
        mt.name = text_of(am, "name");
        if (mt.name.empty()) mt.name = "material" + std::to_string(k);
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

}  // namespace

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
  return text_of(doc, "type") == "CityJSON";
}


RawModel read_cityjson(const std::string& path, const LoadOptions& opt, LoadReport& rep) {
  const Json doc = parse_json(path, read_file(path));
  try {
    return CityJsonReader(path, doc, opt, rep).read();
  } catch (const Json::exception& e) {  // a member of an unexpected type the checks above missed
    fail(path, std::string("malformed CityJSON: ") + e.what());
  }
}

}  // namespace perclod::detail
