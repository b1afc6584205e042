#pragma once
// Mean kinetic energy per particle, and the granular temperature
// T = (2/d) <E_kin> (k_B = 1).

#include "components/mass.hpp"
#include "components/velocity.hpp"
#include "engine/core/deterministic_sum.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/world.hpp"

namespace granflow {

inline const SystemDescription observe_kinetic_energy_description{"observe_kinetic_energy", "mean kinetic energy per particle and temperature T = (2/d)<E_kin>"};

template <int D>
double total_kinetic_energy(const World& world) {
  const auto& v = world.component<Velocity<D>>();
  const auto& m = world.component<Mass>();
  return deterministic_sum(world.size(), [&](std::size_t i) { return 0.5 * m[i] * v[i].squaredNorm(); });
}

template <int D>
class KineticEnergyObserver : public System {
 public:
  std::string name() const override { return "observe_kinetic_energy"; }
  Access access() const override {
    return Access{}.reads<Velocity<D>, Mass>().writes_observable("kinetic_energy", unit::energy).writes_observable("temperature", unit::energy);
  }
  void run(World& world) override {
    const double mean = world.size() ? total_kinetic_energy<D>(world) / static_cast<double>(world.size()) : 0.0;
    auto& store = world.resource<ObservableStore>();
    store.set("kinetic_energy", mean);
    store.set("temperature", 2.0 / D * mean);
  }
};

}  // namespace granflow
