// Every format perclod does not read itself (PLY, glTF/GLB, STL, IFC, DAE,
// FBX), through assimp, after checks that keep assimp from trusting sizes a
// hostile file declares.
#include "readers.h"

#include "perclod/outputs.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

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

// Where a PLY header ends: the start of its end_header line and of the data
// after it (end is npos when there is no such line).
struct PlyHeaderEnd {
  size_t end = std::string::npos, body = 0;
};

// One element a PLY header declares: its count and the fewest bytes one takes.
struct PlyElement {
  std::string name;
  double count = 0, min_bytes = 0;
};

// Finds the header's end: the first line that is exactly "end_header"
// (assimp took "2.0atend_header" for the end and then never returned).
PlyHeaderEnd find_ply_header_end(const std::string& data) {
  PlyHeaderEnd h;  // where the end_header line starts, and the data after it
  for (size_t at = 0; at < data.size();) {
    size_t nl = data.find('\n', at);
    size_t stop = nl == std::string::npos ? data.size() : nl;
    std::string_view l(data.data() + at, stop - at);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    if (l == "end_header") {
      h.end = at;
      h.body = nl == std::string::npos ? data.size() : nl + 1;
      break;
    }
    if (nl == std::string::npos) break;
    at = nl + 1;
  }
  return h;
}

// Parses the header's lines (everything before end_header), failing on any
// line assimp could choke on; returns the elements with their minimum sizes.
std::vector<PlyElement> parse_ply_header(const std::string& path, const std::string& header_text) {
  std::istringstream header(header_text);
  std::string line, format;
  std::vector<PlyElement> elements;
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
      PlyElement e;
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
  return elements;
}

// Fails when the elements need more bytes than the file holds after its header.
void check_ply_sizes(const std::string& path, const std::vector<PlyElement>& elements, double available) {
  double needed = 0;
  const PlyElement* largest = nullptr;
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

// A PLY header's element counts must fit in the bytes after it: at least the
// fixed-size properties (and list counts) per element in binary, at least two
// bytes ("0 ") per value in ASCII.
void check_ply(const std::string& path, const std::string& data) {
  const PlyHeaderEnd h = find_ply_header_end(data);
  if (h.end == std::string::npos)
    fail(path, "PLY file without an 'end_header' line (truncated or not a PLY file)");
  const double available = double(data.size() - h.body);
  const std::vector<PlyElement> elements = parse_ply_header(path, data.substr(0, h.end));
  check_ply_sizes(path, elements, available);
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

}  // namespace

RawModel read_assimp(const std::string& path, LoadReport& rep) {
  const std::string data = read_file(path);  // same existence / readability errors as OBJ
  // Files that claim a format by their magic or their extension: assimp picks
  // its reader by either (a PLY starting "ply?" hung it as well).
  const std::string ext = lower_extension(path);
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

}  // namespace perclod::detail
