#include "weld.h"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <unordered_map>

namespace perclod {
namespace {

struct PosKey {
  uint32_t x, y, z;
  bool operator==(const PosKey&) const = default;
};
struct PosHash {
  size_t operator()(const PosKey& k) const {
    uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
    h ^= (h >> 29) + k.y * 0xBF58476D1CE4E5B9ull;
    h ^= (h >> 31) + k.z * 0x94D049BB133111EBull;
    return size_t(h ^ (h >> 32));
  }
};

uint32_t bits(float f) {
  if (f == 0.0f) f = 0.0f;  // -0 and +0 weld
  uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

std::vector<uint32_t> weld_exact(const Scene& s) {
  size_t n = s.vertex_count();
  std::vector<uint32_t> weld(n);
  std::unordered_map<PosKey, uint32_t, PosHash> first;
  first.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    PosKey k{bits(s.positions[3 * i]), bits(s.positions[3 * i + 1]), bits(s.positions[3 * i + 2])};
    weld[i] = first.try_emplace(k, uint32_t(i)).first->second;
  }
  return weld;
}

uint32_t connected_components(const Scene& s, const std::vector<uint32_t>& weld,
                              std::vector<uint32_t>& component) {
  std::vector<uint32_t> parent(s.vertex_count());
  std::iota(parent.begin(), parent.end(), 0u);
  size_t nt = s.triangle_count();
  for (size_t t = 0; t < nt; ++t) {
    uint32_t a = find_root(parent, weld[s.indices[3 * t]]);
    for (int k = 1; k < 3; ++k) {
      uint32_t b = find_root(parent, weld[s.indices[3 * t + k]]);
      if (a != b) parent[b] = a;
    }
  }
  std::vector<uint32_t> id(s.vertex_count(), UINT32_MAX);
  uint32_t count = 0;
  component.resize(nt);
  for (size_t t = 0; t < nt; ++t) {
    uint32_t r = find_root(parent, weld[s.indices[3 * t]]);
    if (id[r] == UINT32_MAX) id[r] = count++;
    component[t] = id[r];
  }
  return count;
}

}  // namespace perclod
