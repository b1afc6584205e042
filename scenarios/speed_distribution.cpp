// Speed distribution of an elastic gas: all particles start at one speed in
// random directions (a delta distribution) and relax to Maxwell-Boltzmann;
// the equilibrium histogram gathers several snapshots 10 collisions per
// particle apart (Poeschel & Schwager 2005).

#include "engine/run/scenario.hpp"
#include "systems/observables/speed_study.hpp"

namespace granflow::scenarios {

GRANFLOW_REGISTER_SCENARIO(speed_distribution, Scenario{
  .name = "speed_distribution",
  .summary = "relaxation of a one-speed gas to Maxwell-Boltzmann; speed histograms (EDMD)",
  .default_output = "speed_distribution.h5md",
  .keys = [](ConfigSchema& s) { declare_speed_study_keys(s, SamplingDefaults{20.0, 10, 10.0, 0.05}); },
  .build = [](Run& run) {
    if (run.config().integer("system.dimension") == 2)
      build_speed_study<2>(run, {"all"}, {});
    else
      build_speed_study<3>(run, {"all"}, {});
  },
  .adopt = adopt_stored_state,
})

}  // namespace granflow::scenarios
