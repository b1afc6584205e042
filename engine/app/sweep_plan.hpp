#pragma once
// A parameter sweep: which scenario, which configuration keys take which
// values, how many repeats of each parameter point, where the results go and
// which scalar observables the summary table collects. Read from a TOML
// sweep file (docs/sweeps.md); every point's configuration is validated
// against the scenario's schema before anything runs.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/config.hpp"

namespace granflow {

// One run: a parameter point's configuration with its repeat's seed. The
// configuration is the plan's (SweepPlan::run_config), kept once per point:
// a plan of a million runs then costs a few hundred bytes a run.
struct SweepRun {
  std::size_t parameter_point;  // index into SweepPlan::parameter_values
  std::size_t repeat;
  std::int64_t seed;
  std::filesystem::path output;
  double cost = 1.0;  // expected, relative: the product of the plan's cost keys
};

struct SweepPlan {
  std::string scenario;
  std::filesystem::path scenario_file;
  std::filesystem::path directory;
  std::vector<std::string> swept_keys;
  // One row per parameter point, one text value per swept key (as written to the summary).
  std::vector<std::vector<std::string>> parameter_values;
  std::size_t repeats = 1;
  std::vector<std::string> summary;
  std::vector<std::string> cost_keys;
  std::vector<Config> point_configs;  // per parameter point, before the repeat's seed
  std::vector<SweepRun> runs;          // parameter point major, repeat minor

  // The whole configuration of run k.
  Config run_config(std::size_t k) const;
};

// output_directory, when not empty, replaces the file's `output`.
SweepPlan read_sweep_plan(const std::string& sweep_file, const std::string& output_directory = "");

// Seed of repeat r of a point whose configuration has seed `base`: repeat 0
// keeps the base seed, later repeats get well-mixed distinct seeds.
std::int64_t repeat_seed(std::int64_t base, std::size_t repeat);

}  // namespace granflow
