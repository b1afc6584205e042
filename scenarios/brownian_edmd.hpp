#pragma once
// Scenario `brownian_edmd`: see scenarios/brownian_edmd.cpp.

#include "engine/core/config.hpp"
#include "engine/run/scenario.hpp"
#include "systems/observables/ensemble_msd.hpp"
#include "systems/sde/sde_model.hpp"

namespace granflow::scenarios {


struct EdmdMsdResult : EnsembleMsd {
  sde::SdeModel enskog;          // gamma0, D0 (Enskog) and tau0 (Haff) of the initial state
  double temperature0 = 0.0;
  double long_time_slope = 0.0;  // least-squares slope of the MSD over the last decade of times
  double msd_exponent = 0.0;     // gamma of MSD = c + a t^gamma over t >= 100 tau0 (or the last decade)
};
// Mean and standard error over the ensemble's runs, and the theory.
EdmdMsdResult reduce_edmd_msd(const EnsembleResults& results);
// Every run (in parallel, one World each) of one configuration, in memory.
EdmdMsdResult measure_edmd_msd(const Config& config);

}  // namespace granflow::scenarios
