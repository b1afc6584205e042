#pragma once
// Scenarios `langevin_msd` and `udsbm_msd`: see scenarios/sde_msd.cpp.

#include <string>
#include <vector>

#include "engine/config.hpp"
#include "engine/scenario_registry.hpp"
#include "scenarios/run_checkpoint.hpp"
#include "systems/sde/sde_model.hpp"

namespace granflow::scenarios {

const ConfigSchema& langevin_msd_schema();
const ConfigSchema& udsbm_msd_schema();
int run_sde_msd(const Config& config, const RunOptions& options);

// The model a configuration asks for (from the gas or given directly).
sde::SdeModel sde_model_from(const Config& config);

// Ensemble and time-averaged MSD of one configuration, every run done.
struct SdeMsdResult {
  std::vector<double> time, msd, msd_stderr, msd_theory;
  std::vector<double> lag, time_averaged_msd, time_averaged_msd_stderr, ergodicity_breaking;
  double initial_velocity_variance = 0.0;  // per component
};
// With a checkpoint path every finished run is saved there; with `resume`
// the runs saved there are taken instead of rerun.
SdeMsdResult measure_sde_msd(const Config& config, bool progress = false, const RunCheckpoint& checkpoint = {});

}  // namespace granflow::scenarios
