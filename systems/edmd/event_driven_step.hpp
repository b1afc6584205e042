#pragma once
// The EDMD node of a scenario graph: processes events up to the next output
// time (or a stop criterion) and brings every particle to that time, so the
// observers that follow see one synchronised state (seed 002 appendix C.1).

#include <fmt/format.h>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/run_control.hpp"
#include "engine/system.hpp"
#include "systems/edmd/event_driven_gas.hpp"

namespace granflow::edmd {

template <int D>
class EventDrivenStep : public System {
 public:
  EventDrivenStep(EventDrivenGas<D>& gas, AdvanceLimits limits) : gas_(gas), limits_(limits) {}

  std::string name() const override { return "edmd_advance"; }
  Access access() const override {
    return {{RunControl::key},
            {Position<D>::key, Velocity<D>::key, Clock::key, RunControl::key, event_driven_gas_key}};
  }

  void run(World& world) override {
    auto& control = world.resource<RunControl>();
    AdvanceLimits limits = limits_;
    limits.max_pair_collisions = std::min(limits.max_pair_collisions, control.pause_at_pair_collisions);
    StopReason reason = gas_.advance(control.target_time, limits);
    gas_.synchronize(reason == StopReason::reached_time || reason == StopReason::no_events ? control.target_time
                                                                                            : gas_.time());
    if (reason == StopReason::collision_limit && gas_.statistics().pair_collisions < limits_.max_pair_collisions)
      reason = StopReason::reached_time;  // a pause the driver asked for
    auto& clock = world.resource<Clock>();
    clock.time = gas_.time();
    clock.step = static_cast<std::int64_t>(gas_.statistics().pair_collisions);
    switch (reason) {
      case StopReason::collision_limit:
        control.stop = true;
        control.reason = fmt::format("reached the collision limit at t = {:.6g}", gas_.time());
        break;
      case StopReason::energy_limit:
        control.stop = true;
        control.reason = fmt::format("kinetic energy fell to the requested fraction at t = {:.6g}", gas_.time());
        break;
      case StopReason::collapse:
        control.stop = true;
        control.failed = true;
        control.reason = gas_.collapse_message();
        break;
      default: break;
    }
  }

 private:
  EventDrivenGas<D>& gas_;
  AdvanceLimits limits_;
};

}  // namespace granflow::edmd
