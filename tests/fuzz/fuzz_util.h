// Shared by the libFuzzer targets: perclod's readers take paths, so each
// input is written to a file (with the extension that picks the reader) in a
// directory private to this process, then read back by the library.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace perclod::fuzz {

// <tmp>/perclod-fuzz-<pid>: one directory per process, so parallel and
// -fork runs never share a file, and relative references in the input (OBJ
// mtllib, glTF buffer uri) resolve inside it. Removed when the process exits
// normally (a crashing input is saved by libFuzzer, not here).
struct InputDir {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("perclod-fuzz-" + std::to_string(::getpid()));
  InputDir() { std::filesystem::create_directories(path); }
  ~InputDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

// <InputDir>/input<ext>, rewritten for every input.
inline std::string write_input(const uint8_t* data, size_t size, const std::string& ext) {
  static const InputDir dir;
  std::string path = (dir.path / ("input" + ext)).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                 std::streamsize(size));
  return path;
}

}  // namespace perclod::fuzz
