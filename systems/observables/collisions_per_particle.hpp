#pragma once
// Mean number of particle-particle collisions each particle has had:
// 2 x (pair collisions) / N.

#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "systems/edmd/event_driven_gas.hpp"

namespace granflow {

inline const SystemDescription observe_collisions_per_particle_description{"observe_collisions_per_particle", "2 x pair collisions / N"};

template <int D>
class CollisionsPerParticleObserver : public SystemOf<Reads<edmd::EventDrivenGas<D>>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<edmd::EventDrivenGas<D>>, Writes<>>::View;
  std::string name() const override { return "observe_collisions_per_particle"; }
  Access access() const override { return View::access().writes_observable("collisions_per_particle", unit::none); }
  void run_on(View view) override {
    const auto n = static_cast<double>(std::max<std::size_t>(view.size(), 1));
    const auto& gas = view.template read<edmd::EventDrivenGas<D>>();
    view.observables().set("collisions_per_particle", 2.0 * static_cast<double>(gas.statistics().pair_collisions) / n);
  }
};

}  // namespace granflow
