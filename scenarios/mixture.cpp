// A two-mass gas: a fraction of the particles has mass_ratio times the mass
// of the others, all start at one speed. With xi = 1 the species reach
// equipartition (equal mean kinetic energy); with xi < 1 the gas cools
// without reaching it and the heavy species stays hotter (Garzo & Dufty
// 1999). Kinetic energies of all particles and of each species are written
// at short intervals (far below one collision per particle).

#include "scenarios/mixture.hpp"

#include <cmath>

#include "components/mass.hpp"
#include "components/species.hpp"
#include "engine/scenario.hpp"
#include "scenarios/speed_study.hpp"

namespace granflow::scenarios {

std::function<void(World&)> mixture_species(const Config& config) {
  const double heavy_mass = config.real("mixture.mass_ratio") * config.real("system.mass");
  const double fraction = config.real("mixture.heavy_fraction");
  return [heavy_mass, fraction](World& world) {
    auto& species = world.add_component<Species>();
    auto& mass = world.component<Mass>();
    const auto heavy = static_cast<std::size_t>(std::llround(fraction * static_cast<double>(world.size())));
    for (std::size_t i = world.size() - heavy; i < world.size(); ++i) {
      species[i] = 1;
      mass[i] = heavy_mass;
    }
  };
}

GRANFLOW_REGISTER_SCENARIO(mixture, Scenario{
  .name = "mixture",
  .summary = "two-mass gas: equipartition at xi = 1 and its breakdown at xi < 1 (EDMD)",
  .default_output = "mixture.h5md",
  .keys = [](ConfigSchema& s) {
    declare_speed_study_keys(s, SamplingDefaults{10.0, 5, 2.0, 0.002});
    s.real("mixture.mass_ratio", 4.0, 0.0, std::numeric_limits<double>::infinity(),
           "mass of the heavy species over system.mass", true)
        .real("mixture.heavy_fraction", 0.5, 0.0, 1.0, "fraction of the particles that are heavy");
  },
  .build = [](Run& run) {
    const auto species = mixture_species(run.config());
    if (run.config().integer("system.dimension") == 2)
      build_speed_study<2>(run, {"light", "heavy"}, species);
    else
      build_speed_study<3>(run, {"light", "heavy"}, species);
  },
})

}  // namespace granflow::scenarios
