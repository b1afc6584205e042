#pragma once
// The configuration schema of a built-in scenario, as `granflow keys` shows it.

#include <string>

#include "engine/app/cli.hpp"
#include "engine/core/config.hpp"
#include "engine/run/scenario.hpp"

namespace granflow {

inline const ConfigSchema& scenario_schema(const std::string& name) {
  link_builtin_scenarios();
  return scenario_registry().schema(name);
}

}  // namespace granflow
