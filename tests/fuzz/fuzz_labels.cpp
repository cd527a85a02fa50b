// libFuzzer target: the labels file reader (read_labels). A std::exception
// is a rejected file; anything else is a finding.
#include "fuzz_util.h"
#include "perclod/labels_io.h"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string path = perclod::fuzz::write_input(data, size, ".txt");
  try {
    perclod::read_labels(path);
  } catch (const std::exception&) {
  }
  return 0;
}
