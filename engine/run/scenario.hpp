#pragma once
// A scenario as the engine knows it: a name, its configuration keys, and a
// build function that declares one run (engine/run/run.hpp). An ensemble
// scenario runs `members` independent runs of the same build (each with its
// own seed) and reduces what they recorded into the result file.
//
// Scenarios register themselves from their own file:
//   GRANFLOW_REGISTER_SCENARIO(haff_cooling, Scenario{...});
// so the engine includes no scenario, and a program built against the
// installed package adds its own scenarios beside the built-in ones.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/config.hpp"
#include "engine/run/observable_recorder.hpp"

namespace granflow {

class Run;
class H5mdFile;

// What the members of an ensemble recorded, in member order.
struct EnsembleMember {
  ObservableHistory history;
  std::map<std::string, double> derived;
  std::map<std::string, std::string> units;  // of the observables, where declared
  std::string stop_reason;  // why the run ended
};
struct EnsembleResults {
  const Config& config;
  std::vector<EnsembleMember> members;
};

struct Scenario {
  std::string name;
  std::string summary;
  std::string default_output;  // result file when no -o is given
  std::function<void(ConfigSchema&)> keys;
  std::function<void(Run&)> build;
  // Sets the keys a stored starting state determines (initial.from), on the
  // configuration the run then reads; none where the scenario has no such start.
  std::function<void(Config&)> adopt;
  // Ensembles only: how many independent runs, and what the result file gets from them.
  std::function<std::size_t(const Config&)> members;
  std::function<void(const EnsembleResults&, H5mdFile&)> reduce;
  // An ensemble of one member is a plain run, its file the same as without
  // run.runs (frames, end-of-run results); only several members are reduced.
  bool one_member_runs_plain = false;

  bool ensemble() const { return static_cast<bool>(members); }
  // Whether this configuration runs as an ensemble (else as one plain run).
  bool runs_as_ensemble(const Config& config) const {
    return ensemble() && !(one_member_runs_plain && members(config) == 1);
  }
};

class ScenarioRegistry {
 public:
  // Throws on a second scenario of the same name.
  void add(Scenario scenario);
  const Scenario* find(const std::string& name) const;
  std::vector<const Scenario*> all() const;  // by name
  // The scenario's keys and the Runner's own (run.seed, output.checkpoint_*).
  const ConfigSchema& schema(const std::string& name) const;

 private:
  std::map<std::string, Scenario> scenarios_;
  mutable std::map<std::string, std::unique_ptr<ConfigSchema>> schemas_;
};

ScenarioRegistry& scenario_registry();

struct ScenarioRegistrar {
  explicit ScenarioRegistrar(Scenario scenario) { scenario_registry().add(std::move(scenario)); }
};

}  // namespace granflow

// Registers a scenario at static initialisation. `id` names a function the
// build's generated list of built-in scenarios refers to, so a static
// library keeps the scenario's object file when linked.
#define GRANFLOW_REGISTER_SCENARIO(id, ...)                                              \
  extern "C" void granflow_scenario_anchor_##id() {}                                     \
  namespace {                                                                            \
  const ::granflow::ScenarioRegistrar granflow_scenario_registrar_##id{__VA_ARGS__};     \
  }
