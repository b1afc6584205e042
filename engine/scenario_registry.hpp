#pragma once
// The scenarios granflow knows by name, each with its configuration schema
// and its run function.

#include <functional>
#include <string>
#include <vector>

#include "engine/config.hpp"

namespace granflow {

struct RunOptions {
  std::string output_path;  // empty: the scenario's default
  int threads = 0;          // 0: all cores
  bool profile = false;
  bool progress = true;
  bool resume = false;      // continue from OUTPUT.checkpoint
};

// Exit status of a run: 0 done, 3 stopped by a physical failure (e.g. collapse).
struct ScenarioInfo {
  std::string name;
  std::string summary;
  std::function<const ConfigSchema&()> schema;
  std::function<int(const Config&, const RunOptions&)> run;
  bool resumable = false;  // writes checkpoints and continues from them with --resume
};

const std::vector<ScenarioInfo>& all_scenarios();
const ScenarioInfo* find_scenario(const std::string& name);

struct SystemInfo {
  std::string name;
  std::string summary;
};
const std::vector<SystemInfo>& systems_catalogue();

}  // namespace granflow
