// What a system is asked besides run(): by default it keeps nothing on an
// accelerator, so every observer round reads host state and nothing is
// copied; the catalogue holds every described system.

#include "engine/core/system.hpp"

#include <gtest/gtest.h>

#include "engine/core/world.hpp"

namespace granflow {
namespace {

class Counter : public System {
 public:
  std::string name() const override { return "count_runs"; }
  Access access() const override { return Access{}.writes_observable("runs"); }
  void run(World&) override { ++runs; }
  int runs = 0;
};

TEST(System, DefaultsSayTheStateLivesOnTheHost) {
  World world;
  Counter counter;
  System& system = counter;
  system.synchronise_host(world);  // nothing to bring back
  EXPECT_TRUE(system.reads_device_state(world));
  EXPECT_TRUE(system.device_profile().empty());
  system.run(world);
  EXPECT_EQ(counter.runs, 1);
  EXPECT_EQ(system.access().written_observables(), std::vector<std::string>{"runs"});
}

}  // namespace
}  // namespace granflow
