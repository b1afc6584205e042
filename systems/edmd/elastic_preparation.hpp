#pragma once
// An elastic event-driven run that prepares an initial state (equilibrating
// a gas, melting a lattice) for a given number of pair collisions: in slices,
// so that it can report its progress, and watching for interruption between
// events. Stopping at a collision count and going on gives the same event
// sequence as one uninterrupted call, so the slices change nothing.

#include <cstdint>
#include <limits>

#include "engine/run/preparation.hpp"
#include "systems/edmd/event_driven_gas.hpp"

namespace granflow::edmd {

// Returns collision_limit when all collisions were done, no_events when the
// gas came to rest first; throws PreparationInterrupted when interrupted.
template <int D>
StopReason run_elastic_preparation(EventDrivenGas<D>& gas, std::uint64_t pair_collisions,
                                   const Preparation& preparation) {
  constexpr std::uint64_t slices = 100;
  const std::uint64_t start = gas.statistics().pair_collisions;
  StopReason reason = StopReason::collision_limit;
  for (std::uint64_t k = 1; k <= slices && reason == StopReason::collision_limit; ++k) {
    AdvanceLimits limits;
    limits.max_pair_collisions = start + pair_collisions * k / slices;
    limits.interrupt = preparation.interrupt;
    reason = gas.advance(std::numeric_limits<double>::infinity(), limits);
    if (reason == StopReason::interrupted) throw PreparationInterrupted(preparation.phase);
    preparation.progress(static_cast<double>(k) / slices);
  }
  return reason;
}

}  // namespace granflow::edmd
