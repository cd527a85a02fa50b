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

namespace perclod::fuzz {

// <tmp>/perclod-fuzz-<pid>/input<ext>, rewritten for every input. One
// directory per process, so parallel and -fork runs never share a file, and
// relative references in the input (OBJ mtllib, glTF buffer uri) resolve
// inside it.
inline std::string write_input(const uint8_t* data, size_t size, const std::string& ext) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("perclod-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  std::string path = (dir / ("input" + ext)).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                 std::streamsize(size));
  return path;
}

}  // namespace perclod::fuzz
