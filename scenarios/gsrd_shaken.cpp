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

#include "engine/run.hpp"
#include "engine/scenario.hpp"
#include "systems/srd/srd_energy.hpp"
#include "systems/srd/srd_fields.hpp"
#include "systems/srd/srd_height_observer.hpp"
#include "systems/srd/srd_profiles.hpp"
#include "systems/srd/srd_frames.hpp"
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
  auto walls = srd::walls_from<D>(c, cells);
  if (walls.empty())
    for (int side : {-1, +1}) {  // bounce-back floor and ceiling, without ghosts: the floor's motion is the only source
      srd::Wall w;
      w.axis = up;
      w.side = side;
      w.rest = side < 0 ? 0.0 : static_cast<double>(cells[up]);
      w.temperature = c.real("srd.temperature");
      w.ghosts = false;
      walls.push_back(w);
    }
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
  const auto ledger = std::make_shared<srd::EnergyLedger>();
  run.keep("energy", *ledger);
  run.observe<srd::SrdEnergyAccount<D>>(std::make_shared<EverySteps>(1, 1), ledger);
  const auto outputs = std::make_shared<EverySteps>(every);
  srd::add_srd_frames<D>(run, outputs);
  run.observe<srd::SrdEnergyObserver<D>>(outputs, ledger, g);
  run.observe<srd::SrdEnergyWatch>(outputs);
  srd::observe_state<D>(run, outputs);
  run.observe<srd::SrdHeightObserver<D>>(outputs, up, n0);
  double layer_volume = 1.0;
  for (int a = 0; a < D; ++a)
    if (a != up) layer_volume *= cells[a];
  const int layers = cells[up];
  auto sums = std::make_shared<srd::ProfileSums>(layers, D);
  run.keep("profiles", *sums);
  run.observe<srd::SrdProfileSampler<D>>(std::make_shared<EverySteps>(1, warmup + 1), up, 0, sums);
  run.observe<srd::SrdProfileObserver<D>>(std::make_shared<EverySteps>(every, warmup + every), layer_volume, 1.0, sums);
  run.at_finish([sums, layer_volume, layers, n0](H5mdFile& file, const RunOutcome&) {
    const auto overall = sums->overall(layer_volume, 1.0);
    if (sums->samples() == 0) return;
    const auto densest = static_cast<int>(std::max_element(overall.density.begin(), overall.density.end()) -
                                          overall.density.begin());
    const double dense_temperature = overall.temperature[static_cast<std::size_t>(densest)];
    const double floor_temperature = overall.temperature[0];
    file.write_attribute("/observables", "dense_layer_height", densest + 0.5);
    file.write_attribute("/observables", "dense_layer_density", overall.density[static_cast<std::size_t>(densest)] / n0);
    file.write_attribute("/observables", "floor_layer_temperature", floor_temperature);
    file.write_attribute("/observables", "dense_layer_temperature", dense_temperature);
    spdlog::info("profiles over {} steps: densest layer at height {:.1f} of {} ({:.3g} n0, temperature {:.4g}); lowest "
                 "layer {:.3g} n0 at temperature {:.4g}",
                 sums->samples(), densest + 0.5, layers, overall.density[static_cast<std::size_t>(densest)] / n0,
                 dense_temperature, overall.density[0] / n0, floor_temperature);
  });
  run.at_finish([&run, n0, ledger](H5mdFile&, const RunOutcome&) {
    const auto& state = run.world().template resource<srd::SrdCells<D>>();
    const std::uint32_t peak = *std::max_element(state.count.begin(), state.count.end());
    spdlog::info("energy: injected by the floor {:.6g}, dissipated {:.6g}, exchanged in ghost cells {:.6g}", ledger->injected,
                 ledger->dissipated, ledger->ghost_exchange);
    if (peak > 20.0 * n0)
      spdlog::warn("the fluid has collapsed: one cell holds {} particles, {:.0f} times the mean; granular SRD's "
                   "compressibility lets the dense layer's pattern coarsen into one spot",
                   peak, peak / n0);
  });
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
