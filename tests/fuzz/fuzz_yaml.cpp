// libFuzzer target: the YAML readers (yaml-cpp underneath). The same bytes go
// to load_batch_config and load_display_profile, so one corpus covers both
// key sets. A std::exception is a rejected file; anything else is a finding.
#include "fuzz_util.h"
#include "perclod/config.h"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string path = perclod::fuzz::write_input(data, size, ".yaml");
  try {
    perclod::load_batch_config(path);
  } catch (const std::exception&) {
  }
  try {
    perclod::load_display_profile(path);
  } catch (const std::exception&) {
  }
  return 0;
}
