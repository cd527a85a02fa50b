// perclod/labels_io.h - the labels file (docs/usage.md#the-labels-file).
//
//   perclod-labels 1
//   model <triangles> <hash>         (optional: the model's fingerprint, 16 hex digits)
//   triangles N
//   views V
//   view <name> <distance>          (V lines)
//   samples S                        (optional, S > 1: counts are samples, S per pixel)
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
  int samples = 1;  // samples per pixel the counts were taken with
  // The model the labels belong to (the "model" line; files written before it
  // existed have none and are still read).
  bool has_model = false;
  uint64_t model_triangles = 0;
  uint64_t model_hash = 0;
};

// FNV-1a/64 over the scene's float positions and its indices: labels of
// another model (or of the same file loaded with another --scale) differ.
uint64_t model_fingerprint(const Scene& scene);

void write_labels(const std::string& path, const LabelFile& file);
// Throws naming the file and line: malformed lines, negative counts, more
// imperceptible than traced pixels, lines after the last triangle, a triangle
// count the file's size cannot hold.
LabelFile read_labels(const std::string& path);

}  // namespace perclod
