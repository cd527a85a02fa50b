// libFuzzer target: perclod's own OBJ reader (load_scene on a .obj file).
// A std::exception (LoadError for a bad file) is the reader doing its job;
// a crash, hang, sanitizer report or any other exception is a finding.
#include "fuzz_util.h"
#include "perclod/load.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string path = perclod::fuzz::write_input(data, size, ".obj");
  try {
    perclod::load_scene(path);
  } catch (const std::exception&) {
  }
  return 0;
}
