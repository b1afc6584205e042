#pragma once
// The run shared by `speed_distribution` and `mixture` (seed 002 problems
// 1-3): a hard-disk/sphere gas started at one speed, observed at short, even
// time intervals (kinetic energy, per species for a mixture), whose speeds
// are sampled in several snapshots many collisions per particle apart once
// it has equilibrated (appendix C.2), then histogrammed per species against
// Maxwell-Boltzmann.

#include <functional>
#include <string>
#include <vector>

#include "engine/config.hpp"
#include "engine/scenario_registry.hpp"
#include "engine/world.hpp"

namespace granflow::scenarios {

struct SpeedStudy {
  std::string scenario;                   // name, also the default output file stem
  std::vector<std::string> species_names;  // one label per species; a single species needs no Species component
  std::function<void(World&)> customize;   // sets masses/radii/species before placement
};

// Keys of the sampling and output, with defaults for that scenario.
struct SamplingDefaults {
  double equilibration_collisions = 20.0;
  std::int64_t snapshots = 10;
  double collisions_between = 10.0;
  double output_interval = 0.01;
};
void declare_speed_study_keys(ConfigSchema& schema, const SamplingDefaults& defaults);
// Seed 002's gas: 4000 disks (r = 0.003) at one speed in a unit box with reflecting walls, elastic.
void declare_speed_study_gas_keys(ConfigSchema& schema);

int run_speed_study(const Config& config, const RunOptions& options, const SpeedStudy& study);

}  // namespace granflow::scenarios
