// A granular SRD fluid under gravity over a vibrating floor, periodic
// sideways (Fig. 5.1 of the SRD thesis this engine's granular SRD follows;
// the vibrated-bed setting of e.g. Eshuis et al. 2007): the floor moves as
// A sin(2 pi f t) along the walls' axis and gives energy to the particles it
// reflects, gravity and the inelastic collisions take it. The fluid forms a
// dense layer lifted off the floor, resting on a hot dilute layer that is in
// contact with it. Density, temperature and velocity profiles against height,
// fields, the energy balance (injected by the floor = change of kinetic and
// potential energy + dissipated) and, as the sideways pattern coarsens, the
// collapse of the fluid into one dense spot, which the peak cell density
// shows (granular SRD is very compressible; the thesis reports the same).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "engine/run/run.hpp"
#include "engine/run/scenario.hpp"
#include "systems/srd/srd_energy_balance.hpp"
#include "systems/srd/srd_fields.hpp"
#include "systems/srd/srd_frames.hpp"
#include "systems/srd/srd_height_observer.hpp"
#include "systems/srd/srd_profiles.hpp"
#include "systems/srd/srd_setup.hpp"
#include "systems/srd/srd_state_observer.hpp"
#include "systems/srd/srd_watchdog.hpp"

namespace granflow::scenarios {
namespace {

template <int D>
void build(Run& run) {
  const Config& c = run.config();
  const auto cells = srd::cells_from<D>(c);
  constexpr int up = D - 1;  // the walls' axis: z in 3D, y in 2D
  // Bounce-back floor and ceiling, without ghosts: the floor's motion is the only source.
  auto walls = srd::walls_or_pair_across<D>(c, cells, up, false);
  for (srd::Wall& w : walls) {
    if (w.axis != up)
      throw ConfigError(fmt::format("gsrd_shaken has its floor and ceiling across the last axis ({}): walls on axis {} "
                                    "are not part of it", "xyz"[up], "xyz"[w.axis]));
    if (w.side < 0 && !w.moving()) {  // the floor shakes unless its own motion was given
      w.amplitude = c.real("shaking.amplitude");
      w.omega = 2.0 * std::numbers::pi * c.real("shaking.frequency");
    }
  }
  const auto floor = std::find_if(walls.begin(), walls.end(), [](const srd::Wall& w) { return w.side < 0; });
  if (floor->amplitude > 0.25 * cells[up])
    throw ConfigError(fmt::format("shaking.amplitude = {} exceeds a quarter of the height ({} cells)", floor->amplitude,
                                  cells[up]));
  auto force = srd::force_from<D>(c, cells);
  if (c.reals("force.acceleration").empty()) force.acceleration[up] = -c.real("shaking.gravity");
  if (!c.reals("force.slab").empty()) throw ConfigError("gsrd_shaken has gravity everywhere: force.slab is for other scenarios");
  if (c.real("thermostat.temperature") > 0.0)
    throw ConfigError("gsrd_shaken is driven by its floor alone: thermostat.temperature must be 0");
  const auto warmup = c.integer("shaken.warmup_steps");
  const auto every = c.integer("output.every_steps");
  if (warmup >= c.integer("run.steps"))
    throw ConfigError(fmt::format("shaken.warmup_steps = {} leaves no step to sample before run.steps = {}", warmup,
                                  c.integer("run.steps")));
  const double omega = floor->omega, amplitude = floor->amplitude;
  srd::add_srd_fluid<D>(run, walls, force, true);
  srd::add_srd_fields<D>(run, cells);
  const auto n0 = static_cast<double>(c.integer("srd.particles_per_cell"));
  run.derive("floor_velocity_amplitude", amplitude * omega);
  run.derive("shaking_acceleration_ratio", std::abs(force.acceleration[up]) > 0
                                               ? amplitude * omega * omega / std::abs(force.acceleration[up])
                                               : 0.0);
  std::array<double, D> g{};
  for (int a = 0; a < D; ++a) g[a] = force.acceleration[a];
  const auto outputs = std::make_shared<EverySteps>(every);
  srd::add_srd_frames<D>(run, outputs);
  srd::add_energy_balance<D>(run, outputs, g);
  srd::observe_state<D>(run, outputs);
  run.observe<srd::SrdHeightObserver<D>>(outputs, up, n0);
  const auto sums = srd::add_layer_profiles<D>(run, cells, up, warmup, every);
  run.at_finish([sums, volume = srd::layer_volume<D>(cells, up), n0](H5mdFile& file, const RunOutcome&) {
    srd::write_densest_layer(file, *sums, volume, n0);
  });
  srd::warn_when_collapsed(run, n0);
}

}  // namespace

GRANFLOW_REGISTER_SCENARIO(gsrd_shaken, Scenario{
  .name = "gsrd_shaken",
  .summary = "granular SRD under gravity over a vibrating floor: a dense layer over a hot one, energy balance, collapse",
  .default_output = "gsrd_shaken.h5md",
  .keys = [](ConfigSchema& s) {
    srd::SrdDefaults d;
    d.dimension = 3;
    d.cells = {32, 32, 40};
    d.particles_per_cell = 10;
    d.angle = 90.0;
    d.dt = 0.1;
    d.temperature = 1.0;
    d.restitution = 0.9;
    d.diameter = 0.2;
    d.steps = 5000;
    srd::declare_srd_keys(s, d);
    declare_frame_keys(s, "none");
    srd::declare_srd_wall_keys(s);
    s.real("shaking.amplitude", 2.0, 0.0, 1e6, "amplitude A of the floor's motion A sin(2 pi f t)")
        .real("shaking.frequency", 0.1, 0.0, 1e6, "frequency f of the floor's motion")
        .real("shaking.gravity", 0.01, 0.0, 1e6, "gravity g towards the floor where force.acceleration is empty")
        .integer("output.every_steps", 100, 1, 1000000000, "steps between outputs (profile blocks)")
        .integer("shaken.warmup_steps", 1000, 0, 1000000000, "steps before the profiles are sampled");
    s.unit("shaking.amplitude", unit::length).unit("shaking.frequency", unit::rate).unit("shaking.gravity", unit::acceleration);
  },
  .build = build_by_dimension<build<2>, build<3>>,
  .adopt = adopt_stored_state,
})

}  // namespace granflow::scenarios
