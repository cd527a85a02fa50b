// Helpers shared by the facade generator's tests (and by
// e2e/test_cli_facade.cpp, which includes this file by path).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "perclod/facade.h"
#include "perclod/scene.h"

namespace perclod::test::facade_fixtures {

using Vec = std::array<double, 3>;

inline Vec vertex(const Scene& s, uint32_t i) {
  return {s.positions[3 * size_t(i)], s.positions[3 * size_t(i) + 1], s.positions[3 * size_t(i) + 2]};
}
inline Vec corner(const Scene& s, size_t tri, int k) { return vertex(s, s.indices[3 * tri + k]); }

// Everything switched on, small enough to generate quickly.
inline FacadeParams all_on(int floors = 2, int bays = 3, int sides = 1) {
  FacadeParams p;
  p.floors = floors;
  p.bays = bays;
  p.sides = sides;
  p.hidden_interior = p.coplanar_panels = p.subpixel_ornaments = true;
  return p;
}

}  // namespace perclod::test::facade_fixtures
