// Vertex welding by position: quantise to a grid of cell size `tolerance`
// and give each distinct key one welded vertex (a hash table; ids in order of
// first use, so the result is deterministic). With
// `per_component`, the component is part of the key: corners of different
// components never weld, even where the input shares a vertex between them.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

#include "simplify_internal.h"

namespace perclod::detail {

namespace {

struct Key {
  int64_t g, x, y, z;
  bool operator==(const Key& o) const { return g == o.g && x == o.x && y == o.y && z == o.z; }
};

Key make_key(const float* p, uint32_t group, double inv_cell) {
  if (inv_cell > 0)
    return {group, std::llround(p[0] * inv_cell), std::llround(p[1] * inv_cell), std::llround(p[2] * inv_cell)};
  // Exact: bit patterns of the floats (+0 and -0 made equal).
  int32_t b[3];
  for (int a = 0; a < 3; ++a) {
    float v = p[a] == 0.0f ? 0.0f : p[a];
    std::memcpy(&b[a], &v, 4);
  }
  return {group, b[0], b[1], b[2]};
}

}  // namespace

void weld_corners(Work& w, bool per_component, double tolerance) {
  const Scene& s = *w.scene;
  const size_t nv = s.vertex_count();
  // 1. Items: (input vertex, group) pairs in order of first use. Groups are
  // only kept with per_component (otherwise every group is 0).
  std::vector<uint32_t> item_vertex, item_group;
  item_vertex.reserve(nv);
  if (per_component) item_group.reserve(nv);
  auto group_of = [&](uint32_t item) { return per_component ? item_group[item] : 0u; };
  std::vector<uint32_t> primary(nv, UINT32_MAX);  // item of (v, first group seen)
  std::unordered_map<uint64_t, uint32_t> extra;   // items of (v, other groups)
  // Corner -> item here; step 3 turns it into corner -> welded vertex in place.
  std::vector<uint32_t>& corner_item = w.weld.corner;
  corner_item.assign(3 * s.triangle_count(), UINT32_MAX);
  for (uint32_t t : w.faces) {
    uint32_t g = per_component ? s.component_of(t) : 0;
    for (int k = 0; k < 3; ++k) {
      uint32_t v = s.indices[3 * size_t(t) + k];
      uint32_t& p = primary[v];
      uint32_t item;
      if (p == UINT32_MAX) {
        p = item = uint32_t(item_vertex.size());
        item_vertex.push_back(v);
        if (per_component) item_group.push_back(g);
      } else if (group_of(p) == g) {
        item = p;
      } else {
        auto [it, fresh] = extra.try_emplace((uint64_t(v) << 32) | g, uint32_t(item_vertex.size()));
        if (fresh) {
          item_vertex.push_back(v);
          item_group.push_back(g);
        }
        item = it->second;
      }
      corner_item[3 * size_t(t) + k] = item;
    }
  }
  std::vector<uint32_t>().swap(primary);
  // 2. Weld the items by (group, quantised position) with an open-addressing
  // hash table; welded ids follow first use, and a welded vertex keeps the
  // position of its first item. A slot's key is made again from that
  // position when compared (no table of keys: 32 bytes per welded vertex
  // that a fresh process would have to fault in).
  const size_t ni = item_vertex.size();
  const double inv_cell = tolerance > 0 ? 1.0 / tolerance : 0.0;
  size_t cap = 16;
  while (cap < 2 * ni) cap *= 2;
  std::vector<uint32_t> slot(cap, UINT32_MAX);  // welded id per slot
  std::vector<uint32_t> welded_group;           // per welded vertex, with per_component
  std::vector<float>& pos = w.weld.positions;
  pos.clear();
  pos.reserve(3 * ni);
  uint32_t welded = 0;
  // The table is far larger than the cache and the hash scatters
  // neighbouring items, so each item's first slot is worked out kAhead
  // items early and prefetched (a ring of the next kAhead probes).
  struct Probe {
    Key key;
    size_t at;  // first slot to look at
  };
  auto probe_of = [&](size_t i) {
    const Key k = make_key(&s.positions[3 * size_t(item_vertex[i])], group_of(uint32_t(i)), inv_cell);
    const uint64_t h = uint64_t(k.g) * 0x9E3779B97F4A7C15ull ^ uint64_t(k.x) * 0xC2B2AE3D27D4EB4Full ^
                       uint64_t(k.y) * 0x165667B19E3779F9ull ^ uint64_t(k.z) * 0x27D4EB2F165667C5ull;
    const size_t at = size_t(h ^ (h >> 29)) & (cap - 1);
    __builtin_prefetch(&slot[at]);
    return Probe{k, at};
  };
  constexpr size_t kAhead = 16;
  Probe ahead[kAhead];
  for (size_t i = 0; i < std::min(kAhead, ni); ++i) ahead[i] = probe_of(i);
  // Item i's slot ends up holding its welded vertex: item_vertex becomes
  // item -> welded vertex in place (probe_of reads only items after i).
  std::vector<uint32_t>& welded_of_item = item_vertex;
  for (size_t i = 0; i < ni; ++i) {
    const Probe probe = ahead[i % kAhead];
    const float* p = &s.positions[3 * size_t(item_vertex[i])];
    if (i + kAhead < ni) ahead[i % kAhead] = probe_of(i + kAhead);
    auto same = [&](uint32_t id) {
      return make_key(&pos[3 * size_t(id)], per_component ? welded_group[id] : 0u, inv_cell) == probe.key;
    };
    size_t at = probe.at;
    while (slot[at] != UINT32_MAX && !same(slot[at])) at = (at + 1) & (cap - 1);
    if (slot[at] == UINT32_MAX) {
      slot[at] = welded++;
      pos.insert(pos.end(), p, p + 3);
      if (per_component) welded_group.push_back(uint32_t(probe.key.g));
    }
    welded_of_item[i] = slot[at];
  }
  // 3. Corners to welded vertices.
  for (uint32_t& c : corner_item)
    if (c != UINT32_MAX) c = welded_of_item[c];
}

}  // namespace perclod::detail
