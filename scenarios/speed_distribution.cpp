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
    edmd::GasDefaults gas;
    gas.dimension = 2;
    gas.count = 4000;
    gas.radius = 0.003;
    gas.boundary = "reflecting";
    gas.velocity = "fixed_speed";
    gas.restitution = 1.0;
    gas.t_stop = 100.0;
    gas.remove_mean_velocity = false;  // walls do not conserve momentum; keep the one-speed start exact
    edmd::declare_gas_keys(s, gas);
    declare_speed_study_keys(s, SamplingDefaults{20.0, 10, 10.0, 0.05});
    return s;
  }();
  return schema;
}

int run_speed_distribution(const Config& config, const RunOptions& options) {
  return run_speed_study(config, options, SpeedStudy{"speed_distribution", {"all"}, {}});
}

}  // namespace granflow::scenarios
