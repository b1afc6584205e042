// Counter-based random numbers: a pure function of their key, uniform in
// (0, 1) and standard normal, and independent across streams.

#include <gtest/gtest.h>

#include <cmath>

#include "engine/core/rng.hpp"

namespace granflow {
namespace {

TEST(Philox, SameKeySameNumbers) {
  Philox a(1, 42, 7, 1000), b(1, 42, 7, 1000);
  for (int k = 0; k < 100; ++k) EXPECT_EQ(a.uniform(), b.uniform());
}

TEST(Philox, DifferentKeysDiffer) {
  Philox a(1, 42, 7, 1000), b(2, 42, 7, 1000), c(1, 43, 7, 1000), d(1, 42, 8, 1000), e(1, 42, 7, 1001);
  const double x = a.uniform();
  EXPECT_NE(x, b.uniform());
  EXPECT_NE(x, c.uniform());
  EXPECT_NE(x, d.uniform());
  EXPECT_NE(x, e.uniform());
}

TEST(Philox, UniformAndNormalMoments) {
  constexpr int n = 200000;
  double sum = 0, square = 0, normal_sum = 0, normal_square = 0, normal_fourth = 0;
  for (int i = 0; i < n; ++i) {
    Philox random(3, 9, 0, static_cast<std::uint64_t>(i));
    const double u = random.uniform();
    ASSERT_GT(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    square += u * u;
    const double z = random.normal();
    normal_sum += z;
    normal_square += z * z;
    normal_fourth += z * z * z * z;
  }
  // Tolerances: 5 standard errors of each sample moment.
  EXPECT_NEAR(sum / n, 0.5, 5 * std::sqrt(1.0 / 12 / n));
  EXPECT_NEAR(square / n, 1.0 / 3, 5 * std::sqrt(4.0 / 45 / n));
  EXPECT_NEAR(normal_sum / n, 0.0, 5 * std::sqrt(1.0 / n));
  EXPECT_NEAR(normal_square / n, 1.0, 5 * std::sqrt(2.0 / n));
  EXPECT_NEAR(normal_fourth / n, 3.0, 5 * std::sqrt(96.0 / n));
}

}  // namespace
}  // namespace granflow
