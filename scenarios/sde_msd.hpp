#pragma once
// Scenarios `langevin_msd` and `udsbm_msd`: see scenarios/sde_msd.cpp.

#include <string>
#include <vector>

#include "engine/config.hpp"
#include "engine/scenario.hpp"
#include "systems/sde/sde_model.hpp"

namespace granflow::scenarios {


// Ensemble and time-averaged MSD of one configuration, every run done.
struct SdeMsdResult {
  std::vector<double> time, msd, msd_stderr, msd_theory;
  std::vector<double> lag, time_averaged_msd, time_averaged_msd_stderr, ergodicity_breaking;
  double initial_velocity_variance = 0.0;  // per component
};
// Mean and standard error over the ensemble's runs, and the theory.
SdeMsdResult reduce_sde_msd(const EnsembleResults& results);
// Every run of one configuration, in memory.
SdeMsdResult measure_sde_msd(const Config& config);

}  // namespace granflow::scenarios
