#pragma once
// Mean number of particle-particle collisions each particle has had:
// 2 x (pair collisions) / N.

#include "engine/observable_store.hpp"
#include "engine/system.hpp"
#include "systems/edmd/event_driven_gas.hpp"

namespace granflow {

template <int D>
class CollisionsPerParticleObserver : public System {
 public:
  explicit CollisionsPerParticleObserver(const edmd::EventDrivenGas<D>& gas) : gas_(gas) {}
  std::string name() const override { return "observe_collisions_per_particle"; }
  Access access() const override {
    return {{edmd::event_driven_gas_key}, {ObservableStore::access_key("collisions_per_particle")}};
  }
  void run(World& world) override {
    const auto n = static_cast<double>(std::max<std::size_t>(world.size(), 1));
    world.resource<ObservableStore>().set("collisions_per_particle",
                                          2.0 * static_cast<double>(gas_.statistics().pair_collisions) / n);
  }

 private:
  const edmd::EventDrivenGas<D>& gas_;
};

}  // namespace granflow
