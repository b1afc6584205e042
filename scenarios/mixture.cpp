// A two-mass gas (seed 002 problems 2 and 3): a fraction of the particles
// has mass_ratio times the mass of the others, all start at one speed. With
// xi = 1 the species reach equipartition (equal mean kinetic energy); with
// xi < 1 the gas cools without reaching it, the heavy species stays hotter.
// Kinetic energies of all particles and of each species are written at short
// intervals (far below one collision per particle).

#include "scenarios/mixture.hpp"

#include <cmath>

#include "components/mass.hpp"
#include "components/species.hpp"
#include "scenarios/speed_study.hpp"
#include "systems/edmd/gas_setup.hpp"

namespace granflow::scenarios {

const ConfigSchema& mixture_schema() {
  static const ConfigSchema schema = [] {
    ConfigSchema s;
    s.choice("scenario", "mixture", {"mixture"}, "scenario name");
    declare_speed_study_gas_keys(s);
    s.real("mixture.mass_ratio", 4.0, 0.0, std::numeric_limits<double>::infinity(),
           "mass of the heavy species over system.mass", true)
        .real("mixture.heavy_fraction", 0.5, 0.0, 1.0, "fraction of the particles that are heavy");
    declare_speed_study_keys(s, SamplingDefaults{10.0, 5, 2.0, 0.002});
    return s;
  }();
  return schema;
}

std::function<void(World&)> mixture_species(const Config& config) {
  const double heavy_mass = config.real("mixture.mass_ratio") * config.real("system.mass");
  const double fraction = config.real("mixture.heavy_fraction");
  const auto customize = [heavy_mass, fraction](World& world) {
    auto& species = world.add_component<Species>();
    auto& mass = world.component<Mass>();
    const auto heavy = static_cast<std::size_t>(std::llround(fraction * static_cast<double>(world.size())));
    for (std::size_t i = world.size() - heavy; i < world.size(); ++i) {
      species[i] = 1;
      mass[i] = heavy_mass;
    }
  };
  return customize;
}

int run_mixture(const Config& config, const RunOptions& options) {
  return run_speed_study(config, options, SpeedStudy{"mixture", {"light", "heavy"}, mixture_species(config)});
}

}  // namespace granflow::scenarios
