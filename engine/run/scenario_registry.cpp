#include <fmt/format.h>

#include <limits>
#include <stdexcept>

#include "engine/core/key_units.hpp"
#include "engine/run/runner_keys.hpp"
#include "engine/run/scenario.hpp"

namespace granflow {

void ScenarioRegistry::add(Scenario scenario) {
  if (scenario.name.empty() || !scenario.build || !scenario.keys)
    throw std::logic_error("a scenario needs a name, keys and a build function");
  if (scenario.ensemble() != static_cast<bool>(scenario.reduce))
    throw std::logic_error("scenario '" + scenario.name + "': an ensemble needs both members and reduce");
  const std::string name = scenario.name;
  if (!scenarios_.emplace(name, std::move(scenario)).second)
    throw std::logic_error("scenario '" + name + "' is registered twice");
}

const Scenario* ScenarioRegistry::find(const std::string& name) const {
  auto it = scenarios_.find(name);
  return it == scenarios_.end() ? nullptr : &it->second;
}

std::vector<const Scenario*> ScenarioRegistry::all() const {
  std::vector<const Scenario*> out;
  for (const auto& [name, scenario] : scenarios_) out.push_back(&scenario);
  return out;
}

const ConfigSchema& ScenarioRegistry::schema(const std::string& name) const {
  auto cached = schemas_.find(name);
  if (cached != schemas_.end()) return *cached->second;
  const Scenario* scenario = find(name);
  if (!scenario) throw std::logic_error("no scenario '" + name + "'");
  auto schema = std::make_unique<ConfigSchema>();
  schema->choice("scenario", name, {name}, "scenario name");
  scenario->keys(*schema);
  declare_runner_keys(*schema);
  declare_key_units(*schema);
  return *schemas_.emplace(name, std::move(schema)).first->second;
}

ScenarioRegistry& scenario_registry() {
  static ScenarioRegistry registry;
  return registry;
}

}  // namespace granflow
