// EveryTime fires at the same times however far behind it is passed: a
// trigger passed once to a late time continues exactly as one passed at
// every step on the way (the slow reference), and an interval far below the
// time returns at once instead of counting to it. Which firings at a stop
// are a trigger's own.

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
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

// At a run's stop, a firing is the trigger's own where a longer run has it
// too: every step, a period's time; not an end cap or a list's last time,
// which the stop set (Run splits its stop round by this).
TEST(Trigger, AFiringAtTheStopIsOwnOnlyWhereALongerRunHasIt) {
  EveryTime outputs(0.5, 4.3), samples(0.1, 4.3);
  outputs.pass(4.2, 0);
  samples.pass(4.2, 0);
  EXPECT_DOUBLE_EQ(outputs.next_time(), 4.3);  // the cap
  EXPECT_FALSE(outputs.own_firing(4.3, 0));
  EXPECT_DOUBLE_EQ(samples.next_time(), 4.3);  // 43 intervals
  EXPECT_TRUE(samples.own_firing(4.3, 0));

  const EverySteps every(1, 1);
  EXPECT_TRUE(every.own_firing(0.0, 7));

  AtSteps list({0, 10, 100, 350});
  list.pass(0.0, 100);
  EXPECT_EQ(list.next_step(), 350);
  EXPECT_FALSE(list.own_firing(0.0, 350));

  const AnyOf both({std::make_shared<AtSteps>(std::vector<std::int64_t>{350}), std::make_shared<EverySteps>(1)});
  EXPECT_TRUE(both.own_firing(0.0, 350));
  const AnyOf lists({std::make_shared<AtSteps>(std::vector<std::int64_t>{350}),
                     std::make_shared<AtSteps>(std::vector<std::int64_t>{400})});
  EXPECT_FALSE(lists.own_firing(0.0, 350));
}

}  // namespace
}  // namespace granflow
