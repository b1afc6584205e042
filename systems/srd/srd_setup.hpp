#pragma once
// What every SRD scenario shares: its keys (declare_srd_keys), the initial
// fluid (uniform positions, Maxwell-Boltzmann velocities about zero mean,
// optionally the linear profile of the imposed shear) and the step chain:
// streaming, grid shift, binning, cell reduction, rotation, thermostat.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>

#include "components/clock.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/config.hpp"
#include "engine/core/input_error.hpp"
#include "engine/core/memory_check.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/units.hpp"
#include "engine/run/run.hpp"
#include "systems/geometry/slab_domain.hpp"
#include "systems/initial/stored_start.hpp"
#include "systems/srd/cell_binning.hpp"
#include "systems/srd/cell_reduction.hpp"
#include "systems/srd/grid_shift.hpp"
#include "systems/srd/rotation.hpp"
#include "systems/srd/srd_cells.hpp"
#include "systems/srd/srd_domain_step.hpp"
#include "systems/srd/srd_device_backends.hpp"
#include "systems/srd/srd_step_limits.hpp"
#include "systems/srd/srd_walls.hpp"
#include "systems/srd/streaming.hpp"
#include "systems/srd/thermostat.hpp"

namespace granflow::srd {

struct SrdDefaults {
  int dimension = 3;
  std::vector<double> cells{32, 32, 32};
  std::int64_t particles_per_cell = 10;
  double angle = 90.0;
  double dt = 1.0;
  double temperature = 1.0;
  double restitution = 1.0;
  double diameter = 1.0;
  double shear_rate = 0.0;
  double thermostat = 0.0;
  std::int64_t steps = 1000;
};

void declare_srd_keys(ConfigSchema& s, const SrdDefaults& d);

// Walls and a body force, for the scenarios that have them: `walls` as a
// list of tables, each ending one axis on one side, and force.acceleration.
void declare_srd_wall_keys(ConfigSchema& s);

template <int D>
std::vector<Wall> walls_from(const Config& c, const std::array<std::int32_t, D>& cells) {
  std::vector<Wall> walls;
  const auto tables = c.tables("walls");
  for (std::size_t k = 0; k < tables.size(); ++k) {
    const Config& t = tables[k];
    Wall w;
    w.axis = t.text("axis") == "x" ? 0 : t.text("axis") == "y" ? 1 : 2;
    if (w.axis >= D)
      throw ConfigError(fmt::format("walls[{}].axis = {}: the system has {} dimensions", k, t.text("axis"), D));
    w.side = t.text("side") == "lower" ? -1 : +1;
    w.kind = t.text("kind") == "slip" ? WallKind::slip : WallKind::no_slip;
    w.rest = w.side < 0 ? 0.0 : static_cast<double>(cells[w.axis]);
    w.temperature = t.real("temperature") > 0.0 ? t.real("temperature") : c.real("srd.temperature");
    w.amplitude = t.real("amplitude");
    w.ghosts = t.boolean("ghosts");
    w.omega = 2.0 * std::numbers::pi * t.real("frequency");
    if (w.amplitude > 0.25 * cells[w.axis])
      throw ConfigError(fmt::format("walls[{}].amplitude = {} exceeds a quarter of the box along {} ({} cells)", k,
                                    w.amplitude, t.text("axis"), cells[w.axis]));
    for (const Wall& other : walls)
      if (other.axis == w.axis && other.side == w.side)
        throw ConfigError(fmt::format("walls[{}]: axis {} already has a {} wall", k, t.text("axis"), t.text("side")));
    walls.push_back(w);
  }
  for (const Wall& w : walls) {
    const auto partner = std::count_if(walls.begin(), walls.end(), [&](const Wall& o) { return o.axis == w.axis; });
    if (partner != 2)
      throw ConfigError(fmt::format("walls: axis {} has a wall on one side only; give it a lower and an upper wall",
                                    "xyz"[w.axis]));
  }
  if (!walls.empty() && c.real("shear.rate") > 0.0)
    throw ConfigError("walls and shear.rate > 0 (Lees-Edwards planes) cannot be combined");
  return walls;
}

// The walls of `c`, or where it gives none a resting pair across `axis`
// (lower at 0, upper at the box's end) at srd.temperature, with ghost
// particles or without.
template <int D>
std::vector<Wall> walls_or_pair_across(const Config& c, const std::array<std::int32_t, D>& cells, int axis, bool ghosts) {
  auto walls = walls_from<D>(c, cells);
  if (walls.empty())
    for (int side : {-1, +1}) {
      Wall w;
      w.axis = axis;
      w.side = side;
      w.rest = side < 0 ? 0.0 : static_cast<double>(cells[axis]);
      w.temperature = c.real("srd.temperature");
      w.ghosts = ghosts;
      walls.push_back(w);
    }
  return walls;
}

template <int D>
std::array<double, D> acceleration_from(const Config& c) {
  const auto& g = c.reals("force.acceleration");
  std::array<double, D> out{};
  if (g.empty()) return out;
  if (g.size() != D)
    throw ConfigError(fmt::format("force.acceleration has {} entries; system.dimension = {} needs {}", g.size(), D, D));
  if (c.real("shear.rate") > 0.0)
    throw ConfigError("force.acceleration and shear.rate > 0 (Lees-Edwards planes) cannot be combined");
  for (int a = 0; a < D; ++a) out[a] = g[a];
  return out;
}

// force.acceleration with its slab, if any.
template <int D>
BodyForce<D> force_from(const Config& c, const std::array<std::int32_t, D>& cells) {
  BodyForce<D> force;
  const auto g = acceleration_from<D>(c);
  for (int a = 0; a < D; ++a) force.acceleration[a] = g[a];
  const auto& slab = c.reals("force.slab");
  if (slab.empty()) return force;
  const std::string& axis_name = c.text("force.slab_axis");
  const int axis = axis_name == "x" ? 0 : axis_name == "y" ? 1 : 2;
  if (axis >= D)
    throw ConfigError(fmt::format("force.slab_axis = {}: the system has {} dimensions", axis_name, D));
  if (slab.size() != 2 || !(slab[0] < slab[1]))
    throw ConfigError(fmt::format("force.slab must be [from, to] with from < to (it has {} entries{})", slab.size(),
                                  slab.size() == 2 ? fmt::format(": {} and {}", slab[0], slab[1]) : ""));
  if (slab[0] < 0.0 || slab[1] > cells[axis])
    throw ConfigError(fmt::format("force.slab = [{}, {}] leaves the box: along {} it spans [0, {}]", slab[0], slab[1],
                                  axis_name, cells[axis]));
  if (!force.any()) throw ConfigError("force.slab is given but force.acceleration is empty or zero");
  force.slab_axis = axis;
  force.from = slab[0];
  force.to = slab[1];
  return force;
}

inline Dissipation dissipation_from(const Config& c) {
  const std::string& rule = c.text("srd.dissipation");
  return rule == "random_axis" ? Dissipation::random_axis : rule == "whole" ? Dissipation::whole : Dissipation::rotated_plane;
}

template <int D>
std::array<std::int32_t, D> cells_from(const Config& c) {
  const auto& cells = c.reals("system.cells");
  if (cells.size() != D)
    throw ConfigError(fmt::format("system.cells has {} entries; system.dimension = {} needs {}", cells.size(), D, D));
  std::array<std::int32_t, D> out{};
  for (int a = 0; a < D; ++a) {
    if (cells[a] != std::floor(cells[a]))
      throw ConfigError(fmt::format("system.cells[{}] = {} is not a whole number of cells", a, cells[a]));
    out[a] = static_cast<std::int32_t>(cells[a]);
  }
  return out;
}

inline RotationParameters rotation_from(const Config& c) {
  return {c.real("srd.rotation_angle"), c.real("srd.restitution"), c.real("srd.diameter"), c.real("srd.time_step"),
          dissipation_from(c), c.real("shear.rate") > 0.0};
}

// The axis the slabs of a run over ranks lie along: a periodic one, the
// one with the most cells (the last of equals: the slowest index); walls
// then span every slab. Under shear, the last axis: the Lees-Edwards planes
// across y shift particles and cells along x, so x is never split; in 3D z
// keeps the planes inside every slab, in 2D they lie at the slabs'
// periodic edge. -1 where every axis has walls.
template <int D>
int slab_axis_of(const std::array<std::int32_t, D>& cells, const std::array<bool, D>& periodic, double shear_rate) {
  int axis = -1;
  for (int a = D - 1; a >= 0; --a)
    if (periodic[a] && (axis < 0 || cells[a] > cells[axis])) axis = a;
  return shear_rate > 0.0 ? D - 1 : axis;
}

// The step over MPI ranks (srd_domain_step.hpp), for what it offers so far:
// a periodic fluid without a body force, a thermostat or Lees-Edwards planes,
// on the CPU; the rest is refused, naming what to change.
template <int D>
void add_domain_step(Run& run, const SrdCells<D>& state, const BodyForce<D>& force, bool walled, bool by_slab) {
  const Config& c = run.config();
  const int ranks = run.communicator()->size();
  const auto refuse = [&](const std::string& what) {
    throw ConfigError(fmt::format("{} is not yet offered over several ranks (this run has {}); run this one without "
                                  "mpirun",
                                  what, ranks));
  };
  if (c.text("srd.device") != "cpu") refuse(fmt::format("srd.device = \"{}\"", c.text("srd.device")));
  const double rate = c.real("shear.rate");
  std::array<bool, D> periodic{};
  for (int a = 0; a < D; ++a) periodic[a] = !(state.bounded & (1u << a));
  const int axis = slab_axis_of<D>(state.cells, periodic, rate);
  if (axis < 0)
    throw ConfigError(fmt::format("an SRD fluid with walls across every axis cannot be split over {} ranks: the slabs "
                                  "need one periodic axis; run it without mpirun",
                                  ranks));
  // Samplers that run every step read sums the step adds over the ranks
  // (srd_step_sums.hpp), not the whole system gathered each step.
  run.world().template emplace_resource<SrdStepSums<D>>();
  DomainStepPhysics<D> physics;
  physics.axis = axis;
  physics.force = force;
  physics.shear_rate = rate;
  physics.thermostat_temperature = c.real("thermostat.temperature");
  physics.remove_drift = !walled;  // as on one rank: walls fix the frame
  physics.started_by_slab = by_slab;
  DomainBalance balance{c.integer("balance.every_steps"), c.real("balance.threshold"), c.real("balance.cell_weight"),
                        std::make_shared<SlabBounds>()};
  run.keep("slab_bounds", *balance.kept);
  const auto interval = static_cast<std::uint64_t>(run.derived("reorder_interval"));
  run.step<SrdDomainStep<D>>(*run.communicator(), c.real("srd.time_step"), rotation_from(c), run.seed(),
                             c.boolean("srd.grid_shift"), interval, state, physics, balance);
  run.mark_distributed();
  run.derive("ranks", static_cast<double>(ranks));
  run.derive("slab_axis", static_cast<double>(axis));
}

// The initial fluid, the cells resource, the box and the step chain.
template <int D>
void add_srd_fluid(Run& run, std::vector<Wall> walls = {}, BodyForce<D> force = {}, bool record_energy = false) {
  const Config& c = run.config();
  const auto cells = cells_from<D>(c);
  double cell_count = 1.0;
  for (int a = 0; a < D; ++a) cell_count *= cells[a];
  const double particles = cell_count * static_cast<double>(c.integer("srd.particles_per_cell"));
  if (particles > 4.0e9)
    throw ConfigError(fmt::format("{:.3g} particles (system.cells x srd.particles_per_cell) exceed the 2^32 a cell "
                                  "index can count", particles));
  // Position, velocity, cell, order; per cell its sums, scratch and operator.
  require_memory(fmt::format("{:.3g} SRD particles", particles),
                 particles * (2.0 * 8.0 * D + 9.0) + cell_count * 8.0 * (D * D + 4.0 * D + 5.0));
  check_srd_step<D>(c, cells, walls, force, particles);
  const auto n = static_cast<std::size_t>(particles);
  const double rate = c.real("shear.rate");
  const double temperature = c.real("srd.temperature");
  std::array<bool, D> periodic{};
  for (int a = 0; a < D; ++a)
    periodic[a] = std::none_of(walls.begin(), walls.end(), [a](const Wall& w) { return w.axis == a; });
  // Particle frames follow ids given in the order of the initial state
  // (a stored one's order), before the binning sorts the particles.
  const bool frames = c.schema().find("output.positions") && c.text("output.positions") != "none";
  // Over ranks each rank holds only its slab's particles from the start: a
  // generated fluid is made by slab, and a stored one or a resumed run's
  // World is read by slab, block by block.
  const bool on_ranks = run.communicator() && run.communicator()->size() > 1;
  const int by_slab_axis = slab_axis_of<D>(cells, periodic, rate);
  bool by_slab = false;
  Run::OwnedOnResume owned;
  if (on_ranks && by_slab_axis >= 0) {
    // The slabs the step starts from (SrdDomainStep::scatter): the
    // checkpoint's where it was written on as many ranks, else equal ones.
    constexpr const char* axis_names[3] = {"x", "y", "z"};
    SlabDomain slab(run.communicator()->rank(), run.communicator()->size(), cells[by_slab_axis],
                    axis_names[by_slab_axis]);
    SlabBounds kept;
    kept.restore_state(run.kept_state("slab_bounds"));
    if (kept.bounds.size() == slab.bounds.size()) slab.bounds = kept.bounds;
    owned = {Position<D>::key,
             [slab, by_slab_axis](const double* x) { return slab.owner(x[by_slab_axis]) == slab.rank; }};
  }
  run.initial_state([&](World& world) {
    by_slab = on_ranks && by_slab_axis >= 0;
    world.resize(by_slab ? 0 : n);
    auto& x = world.add_component<Position<D>>();
    auto& v = world.add_component<Velocity<D>>();
    if (frames) {
      auto& id = world.add_component<ParticleId>().values;
      std::iota(id.begin(), id.end(), 0u);
    }
    if (starts_from_stored_state(c)) {
      std::array<double, D> edges{};
      for (int a = 0; a < D; ++a) edges[a] = cells[a];
      if (by_slab)
        place_stored_part<D>(world, edges, periodic, StoredFrame(c.text("initial.from"), c.integer("initial.frame")),
                             owned.owns);
      else
        place_stored_state<D>(world, edges, periodic, stored_state_of(c), {0.0, false});
      SrdCells<D> unshifted(cells, world.size());
      SrdCellBinning<D>::sort(world, unshifted);
      return;
    }
    // Particle i from its own random numbers: the same particles on any
    // number of ranks, each rank keeping those of its slab.
    const auto particle = [&](std::size_t i, Vec<D>& xi, Vec<D>& vi) {
      Philox random(stream::srd_initial, run.seed(), 0, i);
      for (int a = 0; a < D; ++a) xi[a] = random.uniform() * cells[a];
      for (int a = 0; a < D; ++a) vi[a] = std::sqrt(temperature) * random.normal();
    };
    // The profile the Lees-Edwards planes drive, so the run starts near its steady state.
    const auto start_velocity = [&](const Vec<D>& xi, Vec<D>& vi, const Vec<D>& mean) {
      vi -= mean;
      if (rate > 0.0) vi[0] += rate * (xi[1] - 0.5 * cells[1]);
    };
    Vec<D> mean = Vec<D>::Zero();
    if (by_slab) {
      // Over ranks each rank holds only its slab's particles from the
      // start (the whole system never fits one rank's memory where ranks
      // are needed for it): every rank draws all of them, once for the mean
      // velocity, added in the same order as on one rank, and once to keep
      // its own. Their order after the sort below is the whole system's
      // order, restricted to the slab.
      constexpr const char* axis_names[3] = {"x", "y", "z"};
      const SlabDomain slab(run.communicator()->rank(), run.communicator()->size(), cells[by_slab_axis],
                            axis_names[by_slab_axis]);
      Vec<D> xi, vi;
      for (std::size_t i = 0; i < n; ++i) {
        particle(i, xi, vi);
        mean += vi;
      }
      mean /= static_cast<double>(n);
      std::vector<std::uint32_t> own;
      for (std::size_t i = 0; i < n; ++i) {
        particle(i, xi, vi);
        if (slab.owner(xi[by_slab_axis]) == slab.rank) own.push_back(static_cast<std::uint32_t>(i));
      }
      world.resize(own.size());
      for (std::size_t k = 0; k < own.size(); ++k) {
        particle(own[k], x[k], v[k]);
        start_velocity(x[k], v[k], mean);
      }
      if (frames) {
        auto& id = world.component<ParticleId>().values;
        std::copy(own.begin(), own.end(), id.begin());
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        particle(i, x[i], v[i]);
        mean += v[i];
      }
      mean /= static_cast<double>(n);
      for (std::size_t i = 0; i < n; ++i) start_velocity(x[i], v[i], mean);
    }
    SrdCells<D> unshifted(cells, world.size());
    SrdCellBinning<D>::sort(world, unshifted);
  }, owned);
  by_slab = by_slab || run.resumed_by_part();
  // The cells of the current state, so that observers at the start see them.
  const bool walled = !walls.empty();
  auto& state = run.world().template emplace_resource<SrdCells<D>>(cells, run.world().size(), std::move(walls));
  state.ghost_fill = static_cast<double>(c.integer("srd.particles_per_cell"));
  state.seed = run.seed();
  SrdStreaming<D>::set_shear(state, rate, run.world().template resource<Clock>().time);
  state.record_moments = rate > 0.0;
  state.record_energy = record_energy;
  if (by_slab) {
    // Rank 0's first gather makes the whole system's cells; the other ranks
    // keep the grid only to describe it.
    if (run.communicator()->rank() > 0) state.release_arrays();
  } else {
    SrdCellBinning<D>::assign(run.world().template component<Position<D>>(), state);
    SrdCellReduction<D>::reduce(run.world(), state);
  }
  std::vector<double> edges(cells.begin(), cells.end());
  std::vector<std::string> boundary;
  for (int a = 0; a < D; ++a) boundary.push_back(state.bounded & (1u << a) ? "none" : "periodic");
  run.box(edges, boundary);
  const double dt = c.real("srd.time_step");
  const double hottest = std::max(temperature, c.real("thermostat.temperature"));
  const auto interval = c.integer("srd.reorder_interval") > 0
                            ? static_cast<std::uint64_t>(c.integer("srd.reorder_interval"))
                            : reorder_interval_for(std::sqrt(hottest) * dt);
  run.derive("reorder_interval", static_cast<double>(interval));
  if (run.communicator() && run.communicator()->size() > 1) {
    add_domain_step<D>(run, state, force, walled, by_slab);
  } else if (c.text("srd.device") != "cpu") {
    add_device_step<D>(run, state, n, force, interval, walled);
  } else {
    run.step<SrdStreaming<D>>(dt, rate, force);
    run.step<SrdGridShift<D>>(run.seed(), c.boolean("srd.grid_shift"));
    run.step<SrdCellBinning<D>>(interval);
    run.step<SrdCellReduction<D>>();
    run.step<SrdRotation<D>>(rotation_from(c), run.seed());
    // Walls fix the frame: the thermostat then keeps the mean flow.
    if (c.real("thermostat.temperature") > 0.0) run.step<SrdThermostat<D>>(c.real("thermostat.temperature"), !walled);
  }
  run.stop_at_step(c.integer("run.steps"));
  run.finished_reason("reached run.steps");
  run.rate("particle-steps/s", [&run, particles] { return particles * static_cast<double>(run.clock().step); });
}

// Compiled once for both dimensions, in srd_setup.cpp: every SRD scenario
// builds its fluid here, and each would otherwise compile every step again.
extern template void add_srd_fluid<2>(Run&, std::vector<Wall>, BodyForce<2>, bool);
extern template void add_srd_fluid<3>(Run&, std::vector<Wall>, BodyForce<3>, bool);

}  // namespace granflow::srd
