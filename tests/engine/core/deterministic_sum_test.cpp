// deterministic_sum gives the same bits on any number of threads, and the
// sum of the terms to round-off.

#include "engine/core/deterministic_sum.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

namespace granflow {
namespace {

double harmonic_terms(std::size_t n) {
  return deterministic_sum(n, [](std::size_t i) { return 1.0 / static_cast<double>(i + 1) * (i % 3 ? 1.0 : -0.7); });
}

TEST(DeterministicSum, SameBitsOnOneAndTwoThreads) {
  const std::size_t n = 1000003;  // several chunks and a partial one
  double one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = harmonic_terms(n);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = harmonic_terms(n);
  }
  EXPECT_EQ(one, two);
  long double reference = 0.0L;
  for (std::size_t i = 0; i < n; ++i) reference += 1.0L / static_cast<long double>(i + 1) * (i % 3 ? 1.0L : -0.7L);
  EXPECT_NEAR(one, static_cast<double>(reference), 1e-12);
  EXPECT_EQ(deterministic_sum(0, [](std::size_t) { return 1.0; }), 0.0);
}

}  // namespace
}  // namespace granflow
