#pragma once
// The EDMD node of a run's per-step schedule: processes events up to the
// Runner's next target (a time, or a pair-collision count, which is the
// Clock's step for event-driven runs) or a stop criterion, and brings every
// particle to that moment, so the observers that follow see one synchronised
// state (Poeschel & Schwager 2005). The gas is the World's
// EventDrivenGas<D> resource.

#include <fmt/format.h>

#include <algorithm>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/run/run_control.hpp"
#include "systems/edmd/event_driven_gas.hpp"

namespace granflow::edmd {

inline const SystemDescription edmd_advance_description{"edmd_advance", "event-driven hard spheres/disks up to the next target time or collision count (cells, O(1) calendar, TC model)"};

template <int D>
using EventDrivenStepBase =
    SystemOf<Reads<RunControl>, Writes<Position<D>, Velocity<D>, Clock, RunControl, EventDrivenGas<D>, EveryColumn>>;

// The gas keeps the particles' columns between synchronisations and re-sorts
// them (World::permute): the step writes every column.
template <int D>
class EventDrivenStep : public EventDrivenStepBase<D> {
 public:
  using View = typename EventDrivenStepBase<D>::View;
  explicit EventDrivenStep(AdvanceLimits limits) : limits_(limits) {}

  std::string name() const override { return "edmd_advance"; }

  void run_on(View view) override {
    auto& gas = view.template write<EventDrivenGas<D>>();
    auto& control = view.template write<RunControl>();
    AdvanceLimits limits = limits_;
    if (control.target_step >= 0)
      limits.max_pair_collisions = std::min(limits.max_pair_collisions, static_cast<std::uint64_t>(control.target_step));
    limits.interrupt = control.interrupt;
    StopReason reason = gas.advance(control.target_time, limits);
    auto& clock = view.template write<Clock>();
    if (reason == StopReason::interrupted) {
      // Left between two events; the engine's own state holds the particles.
      clock.time = gas.time();
      clock.step = static_cast<std::int64_t>(gas.statistics().pair_collisions);
      return;
    }
    gas.synchronize(reason == StopReason::reached_time || reason == StopReason::no_events ? control.target_time
                                                                                          : gas.time());
    if (reason == StopReason::collision_limit && gas.statistics().pair_collisions < limits_.max_pair_collisions)
      reason = StopReason::reached_time;  // the target step, not the run's limit
    clock.time = gas.time();
    clock.step = static_cast<std::int64_t>(gas.statistics().pair_collisions);
    switch (reason) {
      case StopReason::collision_limit:
        control.stop = true;
        control.reason = fmt::format("reached the collision limit at t = {:.6g}", gas.time());
        break;
      case StopReason::energy_limit:
        control.stop = true;
        control.reason = fmt::format("kinetic energy fell to the requested fraction at t = {:.6g}", gas.time());
        break;
      case StopReason::collapse:
        control.stop = true;
        control.failed = true;
        control.reason = gas.collapse_message();
        break;
      default: break;
    }
  }

 private:
  AdvanceLimits limits_;
};

}  // namespace granflow::edmd
