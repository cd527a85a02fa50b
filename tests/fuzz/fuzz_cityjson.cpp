// libFuzzer target: perclod's own CityJSON reader (load_scene on a
// .city.json file). Inputs of odd size are read at LOD 2 (cityjson_lod), the
// others at each object's highest, so both ways of picking geometry are
// fuzzed. A std::exception (LoadError for a bad file) is the reader doing its
// job; a crash, hang, sanitizer report or any other exception is a finding.
#include "fuzz_util.h"
#include "perclod/load.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string path = perclod::fuzz::write_input(data, size, ".city.json");
  perclod::LoadOptions options;
  if (size % 2) options.cityjson_lod = "2";
  try {
    perclod::load_scene(path, options);
  } catch (const std::exception&) {
  }
  return 0;
}
