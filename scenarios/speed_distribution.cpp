// Speed distribution of an elastic gas (seed 002 problem 1; seed 000 sec.
// 4.1.2): all particles start at one speed in random directions (a delta
// distribution) and relax to Maxwell-Boltzmann; the equilibrium histogram
// gathers several snapshots 10 collisions per particle apart.

#include "scenarios/speed_distribution.hpp"

#include "scenarios/speed_study.hpp"
#include "systems/edmd/gas_setup.hpp"

namespace granflow::scenarios {

const ConfigSchema& speed_distribution_schema() {
  static const ConfigSchema schema = [] {
    ConfigSchema s;
    s.choice("scenario", "speed_distribution", {"speed_distribution"}, "scenario name");
    declare_speed_study_gas_keys(s);
    declare_speed_study_keys(s, SamplingDefaults{20.0, 10, 10.0, 0.05});
    return s;
  }();
  return schema;
}

int run_speed_distribution(const Config& config, const RunOptions& options) {
  return run_speed_study(config, options, SpeedStudy{"speed_distribution", {"all"}, {}});
}

}  // namespace granflow::scenarios
