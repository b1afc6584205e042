// Every number a user sets has a unit: each real-valued key of every
// built-in scenario declares one (shown by `granflow keys`), in the
// notation of the result files.

#include "engine/core/key_units.hpp"

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

TEST(KeyUnits, SharedKeysGetTheirUnitUnlessTheScenarioGaveOne) {
  ConfigSchema schema;
  schema.real("run.t_stop", 1.0, 0.0, 1e9, "stop time")
      .real("system.radius", 0.1, 0.0, 1.0, "radius")
      .unit("system.radius", "cm")  // the scenario's own word wins
      .real("scenario.own", 1.0, 0.0, 2.0, "a key no shared table knows");
  declare_key_units(schema);
  EXPECT_EQ(schema.find("run.t_stop")->unit, unit::time);
  EXPECT_EQ(schema.find("system.radius")->unit, "cm");
  EXPECT_TRUE(schema.find("scenario.own")->unit.empty());
  EXPECT_EQ(schema.find("output.interval"), nullptr);  // a key the schema lacks is not added
}

}  // namespace
}  // namespace granflow
