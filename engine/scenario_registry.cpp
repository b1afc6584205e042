#include "engine/scenario_registry.hpp"

#include "scenarios/brownian_edmd.hpp"
#include "scenarios/crater_impact.hpp"
#include "scenarios/haff_cooling.hpp"
#include "scenarios/mixture.hpp"
#include "scenarios/scattering.hpp"
#include "scenarios/sde_msd.hpp"
#include "scenarios/speed_distribution.hpp"

namespace granflow {

const std::vector<ScenarioInfo>& all_scenarios() {
  static const std::vector<ScenarioInfo> all{
      {"haff_cooling", "homogeneous cooling of inelastic hard spheres/disks against Haff's law (EDMD)",
       scenarios::haff_cooling_schema, scenarios::run_haff_cooling, true},
      {"speed_distribution", "relaxation of a one-speed gas to Maxwell-Boltzmann; speed histograms (EDMD)",
       scenarios::speed_distribution_schema, scenarios::run_speed_distribution},
      {"mixture", "two-mass gas: equipartition at xi = 1 and its breakdown at xi < 1 (EDMD)",
       scenarios::mixture_schema, scenarios::run_mixture},
      {"scattering", "scattering angle of a light disk off a heavy one against the impact parameter (EDMD)",
       scenarios::scattering_schema, scenarios::run_scattering},
      {"crater_impact", "a heavy projectile hits a resting bed of disks; crater size and penetration (EDMD)",
       scenarios::crater_impact_schema, scenarios::run_crater_impact},
      {"brownian_edmd", "MSD, diffusivity and time-averaged MSD of the event-driven gas against Enskog theory",
       scenarios::brownian_edmd_schema, scenarios::run_brownian_edmd, true},
      {"langevin_msd", "ensemble and time-averaged MSD of underdamped Langevin particles (SDE; ergodic)",
       scenarios::langevin_msd_schema, scenarios::run_sde_msd, true},
      {"udsbm_msd", "ensemble and time-averaged MSD of underdamped scaled Brownian motion (SDE; not ergodic)",
       scenarios::udsbm_msd_schema, scenarios::run_sde_msd, true},
  };
  return all;
}

const ScenarioInfo* find_scenario(const std::string& name) {
  for (const auto& s : all_scenarios())
    if (s.name == name) return &s;
  return nullptr;
}

const std::vector<SystemInfo>& systems_catalogue() {
  static const std::vector<SystemInfo> all{
      {"edmd_advance", "event-driven hard spheres/disks up to the next output time (cells, O(1) calendar, TC model)"},
      {"observe_kinetic_energy", "mean kinetic energy per particle and temperature T = (2/d)<E_kin>"},
      {"observe_collisions_per_particle", "2 x pair collisions / N"},
      {"observe_kinetic_energy_by_species", "mean kinetic energy per particle of each species of a mixture"},
      {"observe_crater", "crater_size (bed disks displaced beyond a threshold) and projectile_depth"},
      {"sde_advance", "Langevin / UDSBM steps of independent particles (Euler-Maruyama or exact OU), parallel_for"},
      {"observe_msd", "ensemble mean squared displacement from unwrapped positions"},
      {"write_observables", "appends fresh observables to /observables/<name>/{step,time,value}"},
  };
  return all;
}

}  // namespace granflow
