// Vertex welding by position: quantise to a grid of cell size `tolerance`,
// sort, and give each run of equal keys one welded vertex. Sorting (rather
// than hashing) keeps it cache-friendly and deterministic.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "simplify_internal.h"

namespace perclod::detail {

namespace {

struct Key {
  int64_t x, y, z;
  bool operator<(const Key& o) const {
    if (x != o.x) return x < o.x;
    if (y != o.y) return y < o.y;
    return z < o.z;
  }
  bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
};

Key quantise(const float* p, double inv_cell) {
  return {std::llround(p[0] * inv_cell), std::llround(p[1] * inv_cell), std::llround(p[2] * inv_cell)};
}

}  // namespace

Welded weld_vertices(const std::vector<float>& positions, double tolerance) {
  const size_t n = positions.size() / 3;
  Welded w;
  w.remap.assign(n, 0);
  double inv_cell = tolerance > 0 ? 1.0 / tolerance : 0.0;
  std::vector<Key> keys(n);
  for (size_t i = 0; i < n; ++i) {
    const float* p = &positions[3 * i];
    if (inv_cell > 0) {
      keys[i] = quantise(p, inv_cell);
    } else {
      // Bit patterns of the floats: equal positions, equal keys (+0/-0 aside).
      int32_t b[3];
      for (int a = 0; a < 3; ++a) {
        float v = p[a] == 0.0f ? 0.0f : p[a];
        std::memcpy(&b[a], &v, 4);
      }
      keys[i] = {b[0], b[1], b[2]};
    }
  }
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    if (keys[a] == keys[b]) return a < b;  // first input vertex leads its run
    return keys[a] < keys[b];
  });
  w.positions.reserve(positions.size());
  // Welded ids follow first appearance in input order, so output is stable.
  std::vector<uint32_t> leader(n);
  for (size_t i = 0; i < n;) {
    size_t j = i;
    while (j < n && keys[order[j]] == keys[order[i]]) leader[order[j++]] = order[i];
    i = j;
  }
  std::vector<uint32_t> id_of(n, UINT32_MAX);
  for (size_t i = 0; i < n; ++i) {
    uint32_t l = leader[i];
    if (id_of[l] == UINT32_MAX) {
      id_of[l] = uint32_t(w.positions.size() / 3);
      w.positions.insert(w.positions.end(), &positions[3 * l], &positions[3 * l + 3]);
    }
    w.remap[i] = id_of[l];
  }
  return w;
}

}  // namespace perclod::detail
