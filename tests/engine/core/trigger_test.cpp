// EveryTime fires at the same times however far behind it is passed: a
// trigger passed once to a late time continues exactly as one passed at
// every step on the way (the slow reference), and an interval far below the
// time returns at once instead of counting to it.

#include <gtest/gtest.h>

#include <vector>

#include "engine/core/trigger.hpp"

namespace granflow {
namespace {

TEST(EveryTime, AJumpLandsWhereSteppingDoes) {
  for (const double interval : {0.1, 0.3, 1.0 / 3.0, 2.5e-4, 7.0}) {
    for (const double late : {0.0, 0.05, 1.0, 12.345, 299.99, 300.0}) {
      EveryTime stepped(interval, 300.0), jumped(interval, 300.0);
      for (double t = 0.0; t < late; t += 0.01) stepped.pass(t, 0);
      stepped.pass(late, 0);
      jumped.pass(late, 0);
      std::vector<double> a, b;
      for (int k = 0; k < 5; ++k) {
        a.push_back(stepped.next_time());
        b.push_back(jumped.next_time());
        stepped.pass(stepped.next_time(), 0);
        jumped.pass(jumped.next_time(), 0);
      }
      EXPECT_EQ(a, b) << "interval " << interval << ", passed to " << late;
    }
  }
}

TEST(EveryTime, AnIntervalFarBelowTheTimeDoesNotCountToIt) {
  EveryTime tiny(5e-324, 2.0);
  tiny.pass(1.0, 0);  // would take 2e323 increments one by one
  EXPECT_EQ(tiny.next_time(), Trigger::never);
  EveryTime fine(1e-9, 2.0);
  fine.pass(1.0, 0);
  EXPECT_GT(fine.next_time(), 1.0);
  EXPECT_LT(fine.next_time(), 1.0 + 3e-9);
}

}  // namespace
}  // namespace granflow
