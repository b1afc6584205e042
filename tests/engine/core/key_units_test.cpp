// Every number a user sets has a unit: each real-valued key of every
// built-in scenario declares one (shown by `granflow keys`), in the
// notation of the result files.

#include <gtest/gtest.h>

#include "engine/run/scenario.hpp"

namespace granflow {
namespace {

TEST(KeyUnits, EveryRealKeyOfEveryScenarioHasAUnit) {
  std::size_t checked = 0;
  for (const auto* scenario : scenario_registry().all()) {
    for (const auto& spec : scenario_registry().schema(scenario->name).keys()) {
      if (spec.type != ValueType::real && spec.type != ValueType::real_array) continue;
      EXPECT_FALSE(spec.unit.empty()) << scenario->name << ": " << spec.key << " has no unit";
      ++checked;
    }
  }
  EXPECT_GT(checked, 50u);
}

}  // namespace
}  // namespace granflow
