// A two-mass gas: a fraction of the particles has mass_ratio times the mass
// of the others, all start at one speed. With xi = 1 the species reach
// equipartition (equal mean kinetic energy); with xi < 1 the gas cools
// without reaching it and the heavy species stays hotter (Garzo & Dufty
// 1999). Kinetic energies of all particles and of each species are written
// at short intervals (far below one collision per particle).

#include "scenarios/mixture.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <vector>

#include "components/mass.hpp"
#include "components/species.hpp"
#include "engine/core/input_error.hpp"
#include "engine/run/scenario.hpp"
#include "systems/initial/stored_start.hpp"
#include "systems/observables/speed_study.hpp"

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

namespace {

// A stored mixture: species 0 (light) and 1 (heavy), each of one mass, give
// system.mass, mixture.mass_ratio and mixture.heavy_fraction.
void adopt_stored_mixture(Config& config) {
  if (!starts_from_stored_state(config)) return;
  const StoredState s = stored_state_of(config);
  adopt_stored_layout(config, s);
  if (s.species.size() != s.count || s.mass.size() != s.count)
    throw InputError(fmt::format("initial.from: {} has no particle {}; a mixture takes each particle's species (0 "
                                 "light, 1 heavy) and mass as stored",
                                 s.source, s.species.size() != s.count ? "species" : "masses"));
  std::array<std::vector<double>, 2> masses;
  for (std::size_t i = 0; i < s.count; ++i) {
    if (s.species[i] != 0 && s.species[i] != 1)
      throw InputError(fmt::format("initial.from: {}: particle {} is of species {}; a mixture has species 0 (light) "
                                   "and 1 (heavy)",
                                   s.source, i, s.species[i]));
    masses[static_cast<std::size_t>(s.species[i])].push_back(s.mass[i]);
  }
  if (masses[0].empty() || masses[1].empty())
    throw InputError(fmt::format("initial.from: {} holds particles of species {} only; a mixture has both 0 (light) "
                                 "and 1 (heavy)",
                                 s.source, masses[0].empty() ? 1 : 0));
  const double light = uniform(masses[0], "masses of species 0", "system.mass", s);
  const double heavy = uniform(masses[1], "masses of species 1", "mixture.mass_ratio", s);
  config.set("system.mass", light);
  config.set("mixture.mass_ratio", heavy / light);
  config.set("mixture.heavy_fraction", static_cast<double>(masses[1].size()) / static_cast<double>(s.count));
}

}  // namespace

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
  .adopt = adopt_stored_mixture,
})

}  // namespace granflow::scenarios
