// Small helpers for pipeline tests: temporary files, a box, messages.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <unistd.h>

#include "perclod/load.h"
#include "perclod/scene.h"

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

// A closed box of 8 vertices and 6 quads (12 triangles): a small valid scene.
inline Scene box() {
  Scene s;
  s.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  const uint32_t quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  for (auto& q : quads) s.indices.insert(s.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  s.component_names = {"box"};
  return s;
}

// What `f` throws (its what()), "" when it throws nothing.
inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Whether text contains part.
inline bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The LoadError message load_scene gives for path, or "" when it loads.
inline std::string load_error(const std::string& path, const LoadOptions& opt = {}) {
  try {
    load_scene(path, opt);
  } catch (const LoadError& e) {
    return e.what();
  }
  return "";
}

}  // namespace perclod::test
