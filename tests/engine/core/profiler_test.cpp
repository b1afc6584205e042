// The /profile table: calls and wall time per system, in registration
// order, with an accelerator's stages summed by name.

#include "engine/core/profiler.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace granflow {
namespace {

TEST(Profiler, SumsCallsAndTimePerSlotInRegistrationOrder) {
  Profiler profiler;
  const std::size_t a = profiler.register_system("step");
  const std::size_t b = profiler.register_system("observe");
  profiler.record(a, 0.5);
  profiler.record(a, 1.5);
  profiler.record(b, 0.25);
  const auto entries = profiler.entries();
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].system, "step");
  EXPECT_EQ(entries[0].calls, 2u);
  EXPECT_DOUBLE_EQ(entries[0].total_seconds, 2.0);
  EXPECT_DOUBLE_EQ(entries[0].mean_seconds(), 1.0);
  EXPECT_EQ(entries[1].system, "observe");
  EXPECT_DOUBLE_EQ(ProfileEntry{}.mean_seconds(), 0.0);
  const std::string table = profiler.table();
  EXPECT_LT(table.find("step"), table.find("observe"));
}

TEST(Profiler, DeviceStagesAddUpUnderOneName) {
  Profiler profiler;
  profiler.record_device({"srd_device_step/rotate", 10, 0.1});
  profiler.record_device({"srd_device_step/rotate", 5, 0.2});
  const auto entries = profiler.entries();
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].calls, 15u);
  EXPECT_NEAR(entries[0].total_seconds, 0.3, 1e-15);
}

TEST(Profiler, AScopedTimerRecordsTheTimeItLived) {
  Profiler profiler;
  const std::size_t slot = profiler.register_system("sleep");
  {
    ScopedTimer timer(profiler, slot);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const auto entry = profiler.entries().at(0);
  EXPECT_EQ(entry.calls, 1u);
  EXPECT_GE(entry.total_seconds, 0.02);
}

}  // namespace
}  // namespace granflow
