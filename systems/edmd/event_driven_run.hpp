#pragma once
// Puts an event-driven gas into a run: the engine as the World's
// EventDrivenGas<D> resource (its event state carried by checkpoints), the
// step that advances it to each target, its stop criteria and their
// progress, the box, the collision-rate unit of the progress line, and the
// event counts and dissipated energies written at the end. The World must
// hold the particles already (Run::initial_state).

#include <cmath>

#include "components/box.hpp"
#include "engine/run/run.hpp"
#include "systems/edmd/event_driven_gas.hpp"
#include "systems/edmd/event_driven_step.hpp"
#include "systems/edmd/event_statistics_output.hpp"

namespace granflow::edmd {

// `energy0`: the initial kinetic energy that run.min_energy_fraction refers to.
template <int D>
EventDrivenGas<D>& add_event_driven_gas(Run& run, const Box<D>& box, const CollisionParameters& parameters,
                                        const AdvanceLimits& limits, double energy0, bool sort_in_space = true) {
  World& world = run.world();
  if (!world.has_resource<Box<D>>()) world.emplace_resource<Box<D>>(box);
  auto& gas = world.emplace_resource<EventDrivenGas<D>>(world, parameters, sort_in_space);
  run.keep("event_driven_gas", gas);
  if (!run.resuming()) gas.start(0.0);
  run.step<EventDrivenStep<D>>(limits);
  run.box(box.edges(), box.h5md_boundary());
  run.rate("collisions/s", [&gas] { return static_cast<double>(gas.statistics().pair_collisions); });
  if (limits.max_pair_collisions < std::numeric_limits<std::uint64_t>::max()) {
    const auto limit = static_cast<double>(limits.max_pair_collisions);
    run.progress([&gas, limit] { return static_cast<double>(gas.statistics().pair_collisions) / limit; });
  }
  // A cooling gas loses energy geometrically: progress on a log scale.
  if (limits.min_kinetic_energy > 0 && energy0 > limits.min_kinetic_energy) {
    const double span = std::log(energy0 / limits.min_kinetic_energy);
    run.progress([&gas, energy0, span] {
      return gas.kinetic_energy() > 0 ? std::log(energy0 / gas.kinetic_energy()) / span : 1.0;
    });
  }
  run.at_finish([&gas](H5mdFile& file, const RunOutcome&) { write_event_statistics(file, gas.statistics()); });
  return gas;
}

}  // namespace granflow::edmd
