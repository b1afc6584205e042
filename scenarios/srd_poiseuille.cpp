// Poiseuille flow of the SRD fluid: a channel between two no-slip walls
// (bounce-back with ghost particles, Lamura et al. 2001), driven by a body
// force along x, kept at its temperature by the global thermostat (which
// keeps the flow: the walls fix the frame). The steady profile is the
// parabola v(y) = (g / 2 nu) y (L - y); its fitted curvature gives the
// kinematic viscosity, compared with the kinetic plus collisional viscosity
// of Kikuchi et al. 2003, and its values at the walls the slip.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "engine/run/run.hpp"
#include "engine/run/scenario.hpp"
#include "systems/srd/poiseuille_fit.hpp"
#include "systems/srd/srd_fields.hpp"
#include "systems/srd/srd_frames.hpp"
#include "systems/srd/srd_profiles.hpp"
#include "systems/srd/srd_setup.hpp"
#include "systems/srd/srd_state_observer.hpp"
#include "systems/srd/srd_theory.hpp"
#include "systems/srd/srd_watchdog.hpp"

namespace granflow::scenarios {
namespace {

template <int D>
void build(Run& run) {
  const Config& c = run.config();
  const auto cells = srd::cells_from<D>(c);
  const auto walls = srd::walls_or_pair_across<D>(c, cells, 1, true);  // the channel
  for (const auto& w : walls)
    if (w.axis != 1 || w.kind != srd::WallKind::no_slip || w.moving())
      throw ConfigError("srd_poiseuille is a channel between resting no-slip walls across y: give walls with "
                        "axis = \"y\", kind = \"no_slip\" and no motion, or none");
  if (!c.reals("force.slab").empty())
    throw ConfigError("srd_poiseuille drives the whole channel: force.slab is for other scenarios");
  auto force = srd::force_from<D>(c, cells);
  if (c.reals("force.acceleration").empty()) force.acceleration[0] = 0.002;
  const double* acceleration = force.acceleration;
  if (acceleration[0] <= 0.0 || acceleration[1] != 0.0)
    throw ConfigError(fmt::format("srd_poiseuille drives the flow along x: force.acceleration needs x > 0 and y = 0 "
                                  "(it has x = {}, y = {})", acceleration[0], acceleration[1]));
  const auto warmup = c.integer("poiseuille.warmup_steps");
  if (warmup >= c.integer("run.steps"))
    throw ConfigError(fmt::format("poiseuille.warmup_steps = {} leaves no step to sample before run.steps = {}", warmup,
                                  c.integer("run.steps")));
  srd::add_srd_fluid<D>(run, walls, force);
  srd::add_srd_fields<D>(run, cells);
  const double alpha = c.real("srd.rotation_angle") * std::numbers::pi / 180.0;
  const auto n0 = static_cast<double>(c.integer("srd.particles_per_cell"));
  const double dt = c.real("srd.time_step");
  const double temperature = c.real("thermostat.temperature") > 0 ? c.real("thermostat.temperature") : c.real("srd.temperature");
  const double nu = srd::kinetic_viscosity(D, n0, alpha, temperature, dt) + srd::collisional_viscosity(D, n0, alpha, dt);
  run.derive("viscosity_theory", nu);
  run.derive("acceleration", acceleration[0]);
  const auto outputs = std::make_shared<EverySteps>(c.integer("output.every_steps"), warmup + c.integer("output.every_steps"));
  srd::add_srd_frames<D>(run, outputs);
  const auto sums = srd::add_layer_profiles<D>(run, cells, 1, warmup, c.integer("output.every_steps"));
  srd::observe_state<D>(run, std::make_shared<EverySteps>(c.integer("output.every_steps")));
  const double g = acceleration[0], volume = srd::layer_volume<D>(cells, 1);
  run.at_finish([sums, g, nu, layers = cells[1], volume](H5mdFile& file, const RunOutcome&) {
    srd::write_poiseuille_fit(file, srd::fit_poiseuille(*sums, g, layers, volume), nu, sums->samples());
  });
}

}  // namespace

GRANFLOW_REGISTER_SCENARIO(srd_poiseuille, Scenario{
  .name = "srd_poiseuille",
  .summary = "Poiseuille flow of the SRD fluid between no-slip walls: viscosity from the profile's curvature, wall slip",
  .default_output = "srd_poiseuille.h5md",
  .keys = [](ConfigSchema& s) {
    srd::SrdDefaults d;
    d.dimension = 2;
    d.cells = {40, 20};
    d.particles_per_cell = 10;
    d.angle = 130.0;
    d.dt = 0.5;
    d.temperature = 1.0;
    d.thermostat = 1.0;
    d.steps = 6000;
    srd::declare_srd_keys(s, d);
    declare_frame_keys(s, "none");
    srd::declare_srd_wall_keys(s);
    s.integer("output.every_steps", 250, 1, 1000000000, "steps between outputs (profile blocks)")
        .integer("poiseuille.warmup_steps", 1000, 0, 1000000000, "steps before the profiles are sampled");
  },
  .build = build_by_dimension<build<2>, build<3>>,
  .adopt = adopt_stored_state,
})

}  // namespace granflow::scenarios
