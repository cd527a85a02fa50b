// Scene export: OBJ (+ MTL) or GLB, source offset restored.
#include "perclod/export.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <unordered_map>
#include <numeric>
#include <sstream>
#include <stdexcept>

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NOEXCEPTION
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "perclod/outputs.h"

namespace perclod {
namespace fs = std::filesystem;
namespace {

void append_double(std::string& out, double v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  out.append(buf, r.ptr);
}

// OBJ names may not hold white space.
std::string obj_name(const std::string& s) {
  std::string r = s.empty() ? "unnamed" : s;
  for (auto& c : r)
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') c = '_';
  return r;
}

// Material slot of a triangle: its material id, or 0 for the default material
// of a scene without a material array (Scene's contract).
uint32_t material_slot(const Scene& s, size_t t) { return s.material.empty() ? 0 : s.material[t]; }
size_t material_slots(const Scene& s) { return s.material.empty() ? 1 : s.materials.size(); }
Material material_in_slot(const Scene& s, size_t slot) {
  return s.material.empty() ? Material{"default"} : s.materials[slot];
}

std::string component_name(const Scene& s, uint32_t c) {
  return c < s.component_names.size() ? s.component_names[c] : "component_" + std::to_string(c);
}

// GLB normals: corners of a vertex whose faces turn by more than this get
// vertices of their own, so edges stay sharp and fine facets shade smoothly
// (docs/usage.md#export-for-viewers).
constexpr double kCreaseDeg = 30;

// Triangles ordered by component, then material, so each group is written once.
std::vector<uint32_t> triangle_order(const Scene& s) {
  std::vector<uint32_t> order(s.triangle_count());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    uint32_t ca = s.component_of(a), cb = s.component_of(b);
    return ca != cb ? ca < cb : material_slot(s, a) < material_slot(s, b);
  });
  return order;
}

// The vertices a viewer needs to light `tris` as perclod renders them: each
// corner gets the vertex of its source vertex, component and normal group.
// A vertex's corners share a normal while their faces' normals are within
// kCreaseDeg of the group's first face; past it they get a vertex of their
// own (a facade's edge stays sharp, a turned column's facets shade
// smoothly). A group's normal is the sum of its faces' area-weighted
// normals, in the source's axes.
struct CreaseVertices {
  std::vector<uint32_t> source, component;  // per vertex: its source vertex and component
  std::vector<Eigen::Vector3f> normal;      // per vertex: unit length
  std::vector<uint32_t> corner;             // per corner of tris: its vertex
};

Eigen::Vector3d source_position(const Scene& s, uint32_t v) {
  return {s.positions[3 * size_t(v)], s.positions[3 * size_t(v) + 1], s.positions[3 * size_t(v) + 2]};
}
// a / |a|, or zero for a zero or non-finite a (a degenerate face).
Eigen::Vector3d unit_or_zero(const Eigen::Vector3d& a) {
  const double l = a.norm();
  return l > 0 && std::isfinite(l) ? Eigen::Vector3d(a / l) : Eigen::Vector3d::Zero();
}

CreaseVertices crease_vertices(const Scene& s, const std::vector<uint32_t>& tris) {
  using V = Eigen::Vector3d;
  struct Group {
    V first = V::Zero(), sum = V::Zero();
    uint32_t component = 0, out = 0;
  };
  const double cos_crease = std::cos(kCreaseDeg * kPi / 180);
  std::unordered_map<uint32_t, std::vector<Group>> groups;  // source vertex -> its normal groups
  CreaseVertices cv;
  cv.corner.reserve(3 * tris.size());
  std::vector<std::pair<uint32_t, uint32_t>> corner(3 * tris.size());  // (source vertex, group)
  for (size_t i = 0; i < tris.size(); ++i) {
    const uint32_t* f = &s.indices[3 * size_t(tris[i])];
    const V n = (source_position(s, f[1]) - source_position(s, f[0])).cross(source_position(s, f[2]) - source_position(s, f[0]));
    const V u = unit_or_zero(n);
    const uint32_t comp = s.component_of(tris[i]);
    for (int k = 0; k < 3; ++k) {
      std::vector<Group>& gs = groups[f[k]];
      // A degenerate face (no normal) joins the vertex's first group of its component.
      size_t g = 0;
      while (g < gs.size() && (gs[g].component != comp ||
                               (!u.isZero(0) && !gs[g].first.isZero(0) && gs[g].first.dot(u) < cos_crease)))
        ++g;
      if (g == gs.size()) {
        gs.push_back({u, V::Zero(), comp, uint32_t(cv.source.size())});
        cv.source.push_back(f[k]);
        cv.component.push_back(comp);
      } else if (gs[g].first.isZero(0)) {
        gs[g].first = u;  // a group a degenerate face opened takes the first real normal
      }
      gs[g].sum += n;
      corner[3 * i + size_t(k)] = {f[k], uint32_t(g)};
    }
  }
  cv.normal.resize(cv.source.size());
  for (const auto& [v, gs] : groups)
    for (const Group& g : gs) {
      V n = unit_or_zero(g.sum);
      if (n.isZero(0)) n = g.first.isZero(0) ? V(0, 0, 1) : g.first;  // only degenerate faces
      cv.normal[g.out] = n.cast<float>();
    }
  for (const auto& [v, g] : corner) cv.corner.push_back(groups[v][g].out);
  return cv;
}

void export_obj(const Scene& s, const std::string& path) {
  fs::path p(path);
  std::string mtl_name = p.stem().string() + ".mtl";
  std::string mtl;
  for (size_t slot = 0; slot < material_slots(s); ++slot) {
    const Material m = material_in_slot(s, slot);
    mtl += "newmtl " + obj_name(m.name) + "\n";
    // A material the source gave no colour gets none here either: read back,
    // its triangles are drawn in their component's colour as the original's
    // are (a Kd of the default grey made `perclod judge` see every pixel
    // of a LOD of a colourless OBJ changed).
    if (!m.has_color) continue;
    mtl += "Kd ";
    for (int k = 0; k < 3; ++k) append_double(mtl, m.color[k]), mtl += k < 2 ? " " : "\n";
  }
  std::string out = "# perclod export: " + std::to_string(s.triangle_count()) + " triangles, " +
                    std::to_string(s.component_count()) + " components\nmtllib " + mtl_name + "\n";
  out.reserve(s.positions.size() * 14 + s.indices.size() * 9);
  for (size_t v = 0; v < s.vertex_count(); ++v) {
    out += 'v';
    for (int a = 0; a < 3; ++a) out += ' ', append_double(out, double(s.positions[3 * v + a]) + s.offset[a]);
    out += '\n';
  }
  // Normals as the GLB has them (the same crease rule): a `vn` per vertex
  // normal group, each corner "v//vn".
  const std::vector<uint32_t> order = triangle_order(s);
  const CreaseVertices cv = crease_vertices(s, order);
  for (const Eigen::Vector3f& n : cv.normal) {
    out += "vn";
    for (int a = 0; a < 3; ++a) out += ' ', append_double(out, n[a]);
    out += '\n';
  }
  uint32_t comp = UINT32_MAX, mat = UINT32_MAX;
  for (size_t i = 0; i < order.size(); ++i) {
    const uint32_t t = order[i];
    if (s.component_of(t) != comp) {
      comp = s.component_of(t);
      out += "g " + obj_name(component_name(s, comp)) + "\n";
      mat = UINT32_MAX;
    }
    if (material_slot(s, t) != mat) {
      mat = material_slot(s, t);
      out += "usemtl " + obj_name(material_in_slot(s, mat).name) + "\n";
    }
    out += 'f';
    for (int k = 0; k < 3; ++k)
      out += ' ', out += std::to_string(s.indices[3 * size_t(t) + k] + 1), out += "//",
          out += std::to_string(cv.corner[3 * i + size_t(k)] + 1);
    out += '\n';
  }
  write_text_atomic((p.parent_path() / mtl_name).string(), mtl);
  write_text_atomic(path, out);
}

// GLB: glTF 2.0 binary. Positions are float (recentred) in one buffer; the
// source offset is the translation of a root node, in double in the JSON.
// glTF is +Y up: a Z-up source is turned (x, y, z) -> (x, z, -y), offset too.
class GlbBuilder {
 public:
  explicit GlbBuilder(bool z_up) : z_up_(z_up) {}

  // A root node holding the source offset; returns its index.
  int add_root(const Scene& s, const std::string& name) {
    tinygltf::Node root;
    root.name = name;
    const auto t = turn(s.offset);
    root.translation = {t[0], t[1], t[2]};
    model_.nodes.push_back(root);
    return int(model_.nodes.size() - 1);
  }

  // One mesh of a scene's triangles: a primitive per material (materials of
  // equal colour are one), each with vertices, normals, feature ids (the
  // component) and indices of its own; -1 for a scene without triangles.
  int add_mesh(const Scene& s, const std::string& name) {
    tinygltf::Mesh mesh;
    mesh.name = name;
    std::map<int, std::vector<uint32_t>> by_material;  // glTF material -> its triangles, in order
    for (uint32_t t : triangle_order(s)) by_material[material(s, material_slot(s, t))].push_back(t);
    for (const auto& [mat, tris] : by_material) mesh.primitives.push_back(primitive(s, tris, mat));
    if (mesh.primitives.empty()) return -1;
    // Feature ids index these names (EXT_mesh_features keeps no names itself).
    tinygltf::Value::Array names;
    for (uint32_t c = 0; c < std::max<size_t>(1, s.component_count()); ++c)
      names.push_back(tinygltf::Value(component_name(s, c)));
    mesh.extras = tinygltf::Value(tinygltf::Value::Object{{"feature_names", tinygltf::Value(names)}});
    model_.meshes.push_back(mesh);
    return int(model_.meshes.size() - 1);
  }

  // One primitive of `tris`: POSITION and NORMAL turned to glTF's frame, the
  // component of each vertex as its EXT_mesh_features feature id.
  tinygltf::Primitive primitive(const Scene& s, const std::vector<uint32_t>& tris, int mat) {
    const CreaseVertices cv = crease_vertices(s, tris);
    std::vector<float> pos, nrm, feature(cv.component.begin(), cv.component.end());
    pos.reserve(3 * cv.source.size()), nrm.reserve(3 * cv.source.size());
    for (size_t v = 0; v < cv.source.size(); ++v) {
      const auto p = turn(source_position(s, cv.source[v]));
      const auto n = turn(cv.normal[v].cast<double>());
      for (int a = 0; a < 3; ++a) pos.push_back(float(p[a])), nrm.push_back(float(n[a]));
    }
    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = add_vec3(pos, true);
    prim.attributes["NORMAL"] = add_vec3(nrm, false);
    prim.attributes["_FEATURE_ID_0"] = add_accessor(feature.data(), feature.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER,
                                                    TINYGLTF_COMPONENT_TYPE_FLOAT, feature.size(), TINYGLTF_TYPE_SCALAR);
    prim.indices = add_accessor(cv.corner.data(), cv.corner.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER,
                                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, cv.corner.size(), TINYGLTF_TYPE_SCALAR);
    prim.material = mat;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    std::sort(feature.begin(), feature.end());
    const auto count = std::unique(feature.begin(), feature.end()) - feature.begin();
    tinygltf::Value::Object ids{{"featureCount", tinygltf::Value(int(count))}, {"attribute", tinygltf::Value(0)}};
    prim.extensions["EXT_mesh_features"] = tinygltf::Value(tinygltf::Value::Object{
        {"featureIds", tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(ids)})}});
    uses_features_ = true;
    return prim;
  }

  int add_node(const std::string& name, int mesh) {
    tinygltf::Node n;
    n.name = name;
    n.mesh = mesh;
    model_.nodes.push_back(n);
    return int(model_.nodes.size() - 1);
  }
  tinygltf::Node& node(int i) { return model_.nodes[size_t(i)]; }
  tinygltf::Model& model() { return model_; }

  // Serialised in memory, then written with checked syscalls: tinygltf's file
  // writer does not report a failed stream (a full disk gave a truncated GLB).
  void write(const std::vector<int>& scene_nodes, const std::string& path) {
    tinygltf::Scene scene;
    scene.nodes = scene_nodes;
    model_.scenes.push_back(scene);
    model_.defaultScene = 0;
    if (!buffer_.data.empty()) model_.buffers.push_back(buffer_);  // a buffer holds at least one byte
    model_.asset.version = "2.0";
    model_.asset.generator = "perclod";
    if (uses_features_) model_.extensionsUsed.push_back("EXT_mesh_features");
    std::ostringstream glb;
    tinygltf::TinyGLTF gltf;
    if (!gltf.WriteGltfSceneToStream(&model_, glb, false, true) || !glb)
      throw std::runtime_error(path + ": cannot encode GLB");
    write_bytes_atomic(path, glb.str());
  }

 private:
  std::array<double, 3> turn(const std::array<double, 3>& v) const {
    return z_up_ ? std::array<double, 3>{v[0], v[2], -v[1]} : v;
  }
  std::array<double, 3> turn(const Eigen::Vector3d& v) const { return turn(std::array<double, 3>{v[0], v[1], v[2]}); }

  // A float VEC3 accessor of `data`, with min and max when `bounds` (glTF
  // requires them for POSITION).
  int add_vec3(const std::vector<float>& data, bool bounds) {
    const size_t n = data.size() / 3;
    const int acc = add_accessor(data.data(), data.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER,
                                 TINYGLTF_COMPONENT_TYPE_FLOAT, n, TINYGLTF_TYPE_VEC3);
    if (!bounds) return acc;
    auto& a = model_.accessors[size_t(acc)];
    a.minValues = {data[0], data[1], data[2]}, a.maxValues = a.minValues;
    for (size_t v = 1; v < n; ++v)
      for (int k = 0; k < 3; ++k) {
        a.minValues[k] = std::min(a.minValues[k], double(data[3 * v + k]));
        a.maxValues[k] = std::max(a.maxValues[k], double(data[3 * v + k]));
      }
    return acc;
  }

  int add_accessor(const void* data, size_t bytes, int target, int component_type, size_t count, int type) {
    const size_t off = buffer_.data.size();
    const auto* b = static_cast<const unsigned char*>(data);
    buffer_.data.insert(buffer_.data.end(), b, b + bytes);
    while (buffer_.data.size() % 4) buffer_.data.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0, view.byteOffset = off, view.byteLength = bytes, view.target = target;
    model_.bufferViews.push_back(view);
    tinygltf::Accessor a;
    a.bufferView = int(model_.bufferViews.size() - 1);
    a.componentType = component_type, a.count = count, a.type = type;
    model_.accessors.push_back(a);
    return int(model_.accessors.size() - 1);
  }

  // One glTF material per colour (the first slot's name), made on first use:
  // a CityJSON district's thousands of appearance materials are a few colours.
  int material(const Scene& s, uint32_t slot) {
    const Material sm = material_in_slot(s, slot);
    const auto key = std::array<float, 3>{sm.color[0], sm.color[1], sm.color[2]};
    if (auto it = materials_.find(key); it != materials_.end()) return it->second;
    tinygltf::Material m;
    m.name = sm.name;
    m.pbrMetallicRoughness.baseColorFactor = {sm.color[0], sm.color[1], sm.color[2], 1.0};
    // glTF's defaults are metal (metallicFactor 1): a wall is a rough
    // dielectric, lit like perclod's own renders, not a dark mirror.
    m.pbrMetallicRoughness.metallicFactor = 0.0;
    m.pbrMetallicRoughness.roughnessFactor = 1.0;
    m.doubleSided = true;
    model_.materials.push_back(m);
    return materials_[key] = int(model_.materials.size() - 1);
  }

  bool z_up_;
  bool uses_features_ = false;
  tinygltf::Model model_;
  tinygltf::Buffer buffer_;
  std::map<std::array<float, 3>, int> materials_;
};

// One GLB of one scene: root node (the offset) -> one node whose mesh has a
// primitive per material colour, components told apart by feature ids.
void export_glb(const Scene& s, const std::string& path, const ExportOptions& options) {
  GlbBuilder b(options.z_up);
  const int root = b.add_root(s, "model");
  // glTF accessors and buffer views hold at least one element: a scene
  // without triangles (an empty LOD) is the root node alone.
  if (const int mesh = b.add_mesh(s, "model"); mesh >= 0) b.node(root).children = {b.add_node("model", mesh)};
  b.write({root}, path);
}

}  // namespace

void export_lods_glb(const std::vector<const Scene*>& lods, const std::vector<std::string>& names,
                     const std::vector<double>& screen_coverage, const std::string& path,
                     const ExportOptions& options) {
  if (lods.empty()) throw std::invalid_argument(path + ": no LOD to export");
  if (names.size() != lods.size() || screen_coverage.size() != lods.size())
    throw std::invalid_argument(path + ": one name and one screen coverage per LOD are needed");
  for (const Scene* s : lods) try {
      validate(*s);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(path + ": cannot export: " + e.what());
    }
  GlbBuilder b(options.z_up);
  const int root = b.add_root(*lods[0], "model");
  std::vector<int> lod_nodes;
  for (size_t i = 0; i < lods.size(); ++i) {
    const Scene& s = *lods[i];
    lod_nodes.push_back(b.add_node(names[i], b.add_mesh(s, names[i])));
    // Each LOD keeps its own offset; the root holds the finest one's.
    tinygltf::Node& n = b.node(lod_nodes.back());
    std::array<double, 3> d;
    for (int a = 0; a < 3; ++a) d[a] = s.offset[a] - lods[0]->offset[a];
    if (d != std::array<double, 3>{0, 0, 0})
      n.translation = options.z_up ? std::vector<double>{d[0], d[2], -d[1]} : std::vector<double>{d[0], d[1], d[2]};
  }
  b.node(root).children = {lod_nodes[0]};
  if (lods.size() > 1) {
    tinygltf::Value::Array ids, coverage;
    for (size_t i = 1; i < lod_nodes.size(); ++i) ids.push_back(tinygltf::Value(lod_nodes[i]));
    for (double c : screen_coverage) coverage.push_back(tinygltf::Value(c));
    tinygltf::Value::Object ext{{"ids", tinygltf::Value(ids)}};
    b.node(lod_nodes[0]).extensions["MSFT_lod"] = tinygltf::Value(ext);
    b.node(lod_nodes[0]).extras = tinygltf::Value(tinygltf::Value::Object{{"MSFT_screencoverage", tinygltf::Value(coverage)}});
    b.model().extensionsUsed.push_back("MSFT_lod");
  }
  b.write({root}, path);
}

void export_scene(const Scene& s, const std::string& path, const ExportOptions& options) {
  const std::string ext = lower_extension(path);
  try {
    validate(s);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": cannot export: " + e.what());
  }
  if (ext == ".obj") return export_obj(s, path);
  if (ext == ".glb") return export_glb(s, path, options);
  throw std::invalid_argument(path + ": unknown export format '" + ext + "' (use .obj or .glb)");
}

}  // namespace perclod
