// libFuzzer target: load_scene's assimp path (every extension but .obj).
// The extension follows the bytes, so seeds are ordinary files and mutations
// keep reaching the same importer: "ply" -> .ply, "glTF" (binary magic) ->
// .glb, '{' -> .gltf, anything else -> .stl (ASCII "solid" or binary STL).
// A std::exception is a rejected file; anything else is a finding.
#include "fuzz_util.h"
#include "perclod/load.h"

#include <cstring>
#include <exception>

namespace {
const char* extension_for(const uint8_t* data, size_t size) {
  auto starts = [&](const char* p) { return size >= std::strlen(p) && std::memcmp(data, p, std::strlen(p)) == 0; };
  if (starts("ply")) return ".ply";
  if (starts("glTF")) return ".glb";
  size_t i = 0;
  while (i < size && (data[i] == ' ' || data[i] == '\n' || data[i] == '\r' || data[i] == '\t')) ++i;
  if (i < size && data[i] == '{') return ".gltf";
  return ".stl";
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string path = perclod::fuzz::write_input(data, size, extension_for(data, size));
  try {
    perclod::load_scene(path);
  } catch (const std::exception&) {
  }
  return 0;
}
