// Scene export: OBJ (+ MTL) or GLB, source offset restored.
#include "perclod/export.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <numeric>
#include <sstream>
#include <stdexcept>

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NOEXCEPTION
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>

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

void export_obj(const Scene& s, const std::string& path) {
  fs::path p(path);
  std::string mtl_name = p.stem().string() + ".mtl";
  std::string mtl;
  for (size_t slot = 0; slot < material_slots(s); ++slot) {
    const Material m = material_in_slot(s, slot);
    mtl += "newmtl " + obj_name(m.name) + "\nKd ";
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
  uint32_t comp = UINT32_MAX, mat = UINT32_MAX;
  for (uint32_t t : triangle_order(s)) {
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
    for (int k = 0; k < 3; ++k) out += ' ', out += std::to_string(s.indices[3 * size_t(t) + k] + 1);
    out += '\n';
  }
  write_text_atomic((p.parent_path() / mtl_name).string(), mtl);
  write_text_atomic(path, out);
}

// GLB: one primitive per material (one node per component would explode for
// 100k-component cities). Components are kept only by OBJ export.
void export_glb(const Scene& s, const std::string& path) {
  tinygltf::Model model;
  tinygltf::Buffer buffer;
  auto push = [&](const void* data, size_t bytes) {
    size_t off = buffer.data.size();
    const auto* b = static_cast<const unsigned char*>(data);
    buffer.data.insert(buffer.data.end(), b, b + bytes);
    while (buffer.data.size() % 4) buffer.data.push_back(0);
    return off;
  };
  Bounds bb = scene_bounds(s);
  size_t pos_off = push(s.positions.data(), s.positions.size() * sizeof(float));
  model.bufferViews.push_back({});
  auto& pv = model.bufferViews.back();
  pv.buffer = 0, pv.byteOffset = pos_off, pv.byteLength = s.positions.size() * sizeof(float);
  pv.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  tinygltf::Accessor pa;
  pa.bufferView = 0, pa.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT, pa.count = s.vertex_count();
  pa.type = TINYGLTF_TYPE_VEC3;
  pa.minValues = {bb.lo[0], bb.lo[1], bb.lo[2]};
  pa.maxValues = {bb.hi[0], bb.hi[1], bb.hi[2]};
  // Unreferenced vertices may lie outside the triangle bounds: widen to all vertices.
  for (size_t v = 0; v < s.vertex_count(); ++v)
    for (int a = 0; a < 3; ++a) {
      pa.minValues[a] = std::min(pa.minValues[a], double(s.positions[3 * v + a]));
      pa.maxValues[a] = std::max(pa.maxValues[a], double(s.positions[3 * v + a]));
    }
  model.accessors.push_back(pa);
  tinygltf::Mesh mesh;
  for (size_t m = 0; m < material_slots(s); ++m) {
    std::vector<uint32_t> idx;
    for (size_t t = 0; t < s.triangle_count(); ++t)
      if (material_slot(s, t) == m) idx.insert(idx.end(), &s.indices[3 * t], &s.indices[3 * t] + 3);
    if (idx.empty()) continue;
    size_t off = push(idx.data(), idx.size() * 4);
    tinygltf::BufferView iv;
    iv.buffer = 0, iv.byteOffset = off, iv.byteLength = idx.size() * 4;
    iv.target = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
    model.bufferViews.push_back(iv);
    tinygltf::Accessor ia;
    ia.bufferView = int(model.bufferViews.size() - 1), ia.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    ia.count = idx.size(), ia.type = TINYGLTF_TYPE_SCALAR;
    model.accessors.push_back(ia);
    const Material sm = material_in_slot(s, m);
    tinygltf::Material mat;
    mat.name = sm.name;
    mat.pbrMetallicRoughness.baseColorFactor = {sm.color[0], sm.color[1], sm.color[2], 1.0};
    mat.doubleSided = true;
    model.materials.push_back(mat);
    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = 0;
    prim.indices = int(model.accessors.size() - 1);
    prim.material = int(model.materials.size() - 1);
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    mesh.primitives.push_back(prim);
  }
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.translation = {s.offset[0], s.offset[1], s.offset[2]};  // double in the JSON: exact
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  model.buffers.push_back(buffer);
  model.asset.version = "2.0";
  model.asset.generator = "perclod";
  // Serialised in memory, then written with checked syscalls: tinygltf's file
  // writer does not report a failed stream (a full disk gave a truncated GLB).
  std::ostringstream glb;
  tinygltf::TinyGLTF gltf;
  if (!gltf.WriteGltfSceneToStream(&model, glb, false, true) || !glb)
    throw std::runtime_error(path + ": cannot encode GLB");
  write_bytes_atomic(path, glb.str());
}

}  // namespace

void export_scene(const Scene& s, const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  try {
    validate(s);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": cannot export: " + e.what());
  }
  if (ext == ".obj") return export_obj(s, path);
  if (ext == ".glb") return export_glb(s, path);
  throw std::invalid_argument(path + ": unknown export format '" + ext + "' (use .obj or .glb)");
}

}  // namespace perclod
