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
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"

namespace granflow {

inline const SystemDescription observe_kinetic_energy_description{"observe_kinetic_energy", "mean kinetic energy per particle and temperature T = (2/d)<E_kin>"};

template <int D>
double total_kinetic_energy(const Velocity<D>& v, const Mass& m) {
  return deterministic_sum(v.size(), [&](std::size_t i) { return 0.5 * m[i] * v[i].squaredNorm(); });
}
template <int D>
double total_kinetic_energy(const World& world) {
  return total_kinetic_energy<D>(world.component<Velocity<D>>(), world.component<Mass>());
}

template <int D>
class KineticEnergyObserver : public SystemOf<Reads<Velocity<D>, Mass>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<Velocity<D>, Mass>, Writes<>>::View;
  std::string name() const override { return "observe_kinetic_energy"; }
  Access access() const override {
    return View::access().writes_observable("kinetic_energy", unit::energy).writes_observable("temperature", unit::energy);
  }
  void run_on(View view) override {
    const double total = total_kinetic_energy<D>(view.template read<Velocity<D>>(), view.template read<Mass>());
    const double mean = view.size() ? total / static_cast<double>(view.size()) : 0.0;
    view.observables().set("kinetic_energy", mean);
    view.observables().set("temperature", 2.0 / D * mean);
  }
};

}  // namespace granflow
