#pragma once
// The configuration schema of a built-in scenario, as `granflow keys` shows it.

#include <string>

#include "engine/cli.hpp"
#include "engine/config.hpp"
#include "engine/scenario.hpp"

namespace granflow {

inline const ConfigSchema& scenario_schema(const std::string& name) {
  link_builtin_scenarios();
  return scenario_registry().schema(name);
}

}  // namespace granflow
