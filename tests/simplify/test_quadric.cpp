// The quadric helpers the collapse simplifier decides with (simplify/src/quadric.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "quadric.h"

namespace {

using perclod::detail::Quadric;
using perclod::detail::root_within;

bool by_root(double e2, double t) { return std::sqrt(e2) <= t; }

TEST(Quadric, EvalIsTheSumOfSquaredPlaneDistances) {
  Quadric q;
  q.add_plane(0, 0, 1, -2, 1.0);  // z = 2
  q.add_plane(1, 0, 0, 0, 3.0);   // x = 0, weight 3
  EXPECT_DOUBLE_EQ(q.eval(1, 5, 2), 3.0);
  EXPECT_DOUBLE_EQ(q.eval(0, 0, 5), 9.0);
  EXPECT_DOUBLE_EQ((q + q).eval(1, 5, 4), 2 * (4.0 + 3.0));
}

// The collapser evaluates both ends of an edge with eval2 and a collapse's
// error with eval: every lane must be eval's value to the bit (the costs
// order the collapses), including the clamp of a rounding below 0 and NaN.
TEST(Quadric, Eval2LanesAreEvalToTheBit) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), coord(-500.0, 500.0);
  auto same_bits = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  int clamped = 0;
  for (int i = 0; i < 20000; ++i) {
    Quadric q;
    double p[2][3];
    for (auto& pt : p)
      for (double& c : pt) c = coord(rng);
    for (int k = 0; k < 1 + i % 5; ++k) {  // planes through p[0], where the error rounds about 0
      double n[3] = {u(rng), u(rng), u(rng)};
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (double& c : n) c /= len;
      q.add_plane(n[0], n[1], n[2], -(n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2]), 1 + u(rng));
    }
    const perclod::detail::Double2 e =
        q.eval2(perclod::detail::Double2{p[0][0], p[1][0]}, perclod::detail::Double2{p[0][1], p[1][1]},
                perclod::detail::Double2{p[0][2], p[1][2]});
    for (int s = 0; s < 2; ++s) {
      // eval's formula written out in scalar code; at p[0], on every plane,
      // it rounds below 0 for some of these.
      const double x = p[s][0], y = p[s][1], z = p[s][2];
      const double raw = q.a2 * x * x + 2 * q.ab * x * y + 2 * q.ac * x * z + 2 * q.ad * x + q.b2 * y * y +
                         2 * q.bc * y * z + 2 * q.bd * y + q.c2 * z * z + 2 * q.cd * z + q.d2;
      const double want = raw > 0 ? raw : 0.0;
      clamped += raw <= 0;
      ASSERT_TRUE(same_bits(e[s], want)) << "lane " << s << ": " << e[s] << " against " << want;
      ASSERT_TRUE(same_bits(q.eval(x, y, z), want)) << "eval at lane " << s << "'s point";
    }
  }
  EXPECT_GT(clamped, 100);  // the clamp was exercised
  Quadric nan;
  nan.d2 = std::nan("");
  const perclod::detail::Double2 one = {1, 1};
  EXPECT_EQ(nan.eval2(one, one, one)[1], 0.0);
  EXPECT_EQ(nan.eval(1, 1, 1), 0.0);
}

// The shortcut must decide exactly as comparing the root: the collapse
// order, and so the output, depend on it.
TEST(Quadric, RootWithinDecidesAsTheRootDoesAtTheEdges) {
  const double inf = std::numeric_limits<double>::infinity();
  for (double t : {0.0, 1e-200, 1e-160, 1e-150, 3e-8, 0.0330, 1.0, 7.25, 1e150, 1e160, inf}) {
    const double t2 = t * t;
    for (double e2 : {0.0, t2, std::nextafter(t2, 0.0), std::nextafter(t2, inf), t2 * (1 - 1e-9),
                      t2 * (1 + 1e-9), t2 * (1 - 2e-9), t2 * (1 + 2e-9), t2 * 0.5, t2 * 2, inf}) {
      EXPECT_EQ(root_within(e2, t), by_root(e2, t)) << "e2 " << e2 << " t " << t;
    }
    // The squares of t's neighbours, where rounding t * t matters most.
    for (double u : {std::nextafter(t, 0.0), t, std::nextafter(t, inf)})
      EXPECT_EQ(root_within(u * u, t), by_root(u * u, t)) << "u " << u << " t " << t;
  }
  EXPECT_FALSE(root_within(std::nan(""), 1.0));
}

TEST(Quadric, RootWithinDecidesAsTheRootDoesOnRandomValues) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  std::uniform_int_distribution<int> exponent(-60, 60);
  std::uniform_int_distribution<int> ulps(-4, 4);
  for (int i = 0; i < 200000; ++i) {
    const double t = std::ldexp(mantissa(rng), exponent(rng));
    double e;  // a root near t, within a few ulps half the time
    if (i % 2) {
      e = t;
      for (int k = ulps(rng); k != 0; k += k > 0 ? -1 : 1) e = std::nextafter(e, k > 0 ? 1e300 : 0.0);
    } else {
      e = t * mantissa(rng) * (i % 4 == 0 ? 0.5 : 1.0);
    }
    const double e2 = e * e;
    ASSERT_EQ(root_within(e2, t), by_root(e2, t)) << "e " << e << " t " << t;
  }
}

}  // namespace
