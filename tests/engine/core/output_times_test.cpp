// Output times: evenly and log-spaced, and the log-spaced ones as whole
// steps, against values worked out by hand.

#include "engine/core/output_times.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace granflow {
namespace {

TEST(OutputTimes, LinearTimesEndAtTheStopTime) {
  EXPECT_EQ(linear_output_times(1.0, 0.25), (std::vector<double>{0.0, 0.25, 0.5, 0.75, 1.0}));
  // A stop between two intervals is the last time, once.
  EXPECT_EQ(linear_output_times(0.6, 0.25), (std::vector<double>{0.0, 0.25, 0.5, 0.6}));
}

TEST(OutputTimes, LogTimesFollowTheDecades) {
  const auto t = log_output_times(10.0, 0.1, 2);  // 0, 0.1, 0.316, 1, 3.16, 10
  ASSERT_EQ(t.size(), 6u);
  EXPECT_EQ(t.front(), 0.0);
  EXPECT_NEAR(t[2], std::sqrt(0.1), 1e-15);
  EXPECT_NEAR(t[4], std::sqrt(10.0), 1e-14);
  EXPECT_EQ(t.back(), 10.0);
  EXPECT_THROW(log_output_times(1e300, 1e-300, 1000), ConfigError);  // far more than max_output_times
}

TEST(OutputTimes, LogStepsAreWholeIncreasingAndEndAtTheLastStep) {
  // Steps 1, 10^(1/3) = 2.15, 4.64, 10, ... of dt = 1 up to 40: rounded, repeats dropped.
  EXPECT_EQ(log_output_steps(40.0, 1.0, 3, 1.0), (std::vector<std::int64_t>{0, 1, 2, 5, 10, 22, 40}));
  // With dt = 0.1 the times 0.01 and 0.0316 round to step 0 and are dropped.
  EXPECT_EQ(log_output_steps(1.0, 0.01, 2, 0.1), (std::vector<std::int64_t>{0, 1, 3, 10}));
}

}  // namespace
}  // namespace granflow
