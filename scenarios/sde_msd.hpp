#pragma once
// Scenarios `langevin_msd` and `udsbm_msd`: see scenarios/sde_msd.cpp.

#include "engine/core/config.hpp"
#include "engine/run/scenario.hpp"
#include "systems/observables/ensemble_msd.hpp"

namespace granflow::scenarios {


// Ensemble and time-averaged MSD of one configuration, every run done.
struct SdeMsdResult : EnsembleMsd {
  double initial_velocity_variance = 0.0;  // per component
};
// Mean and standard error over the ensemble's runs, and the theory.
SdeMsdResult reduce_sde_msd(const EnsembleResults& results);
// Every run of one configuration, in memory.
SdeMsdResult measure_sde_msd(const Config& config);

}  // namespace granflow::scenarios
