// Small helpers for pipeline tests: temporary files.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace perclod::test {

// A fresh directory under the system temp dir, removed at the end of the test.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name) {
    path = std::filesystem::temp_directory_path() /
           ("perclod-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string file(const std::string& name, const std::string& text) const {
    auto p = (path / name).string();
    std::ofstream(p) << text;
    return p;
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

}  // namespace perclod::test
