// perclod/labels_io.h - the labels file (documented in README.md).
//
//   perclod-labels 1
//   triangles N
//   views V
//   view <name> <distance>          (V lines)
//   <label> <traced> <imperceptible> (N lines, label one of P I U, counts summed over views)
//
// Labels are the combined ones (perceptible in any view wins; undisplayable only
// when undisplayable in every view).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "perclod/scene.h"

namespace perclod {

struct LabelFile {
  std::vector<Label> labels;
  std::vector<uint32_t> traced, imperceptible;  // per triangle, summed over views
  std::vector<std::pair<std::string, double>> views;
};

void write_labels(const std::string& path, const LabelFile& file);
LabelFile read_labels(const std::string& path);  // throws naming the file and line

}  // namespace perclod
