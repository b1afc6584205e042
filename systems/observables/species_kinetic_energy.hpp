#pragma once
// Mean kinetic energy per particle of each species of a mixture, observable
// `kinetic_energy_by_species` (one value per species, in species order).

#include <string>
#include <vector>

#include "components/mass.hpp"
#include "components/species.hpp"
#include "components/velocity.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"

namespace granflow {

inline const SystemDescription observe_kinetic_energy_by_species_description{"observe_kinetic_energy_by_species", "mean kinetic energy per particle of each species of a mixture"};

template <int D>
std::vector<double> species_kinetic_energies(const Velocity<D>& v, const Mass& m, const Species& species,
                                             std::size_t species_count) {
  std::vector<double> energy(species_count, 0.0), members(species_count, 0.0);
  for (std::size_t i = 0; i < v.size(); ++i) {
    energy[species[i]] += 0.5 * m[i] * v[i].squaredNorm();
    members[species[i]] += 1.0;
  }
  for (std::size_t s = 0; s < species_count; ++s) energy[s] = members[s] > 0 ? energy[s] / members[s] : 0.0;
  return energy;
}
template <int D>
std::vector<double> species_kinetic_energies(const World& world, std::size_t species_count) {
  return species_kinetic_energies<D>(world.component<Velocity<D>>(), world.component<Mass>(),
                                     world.component<Species>(), species_count);
}

template <int D>
class SpeciesKineticEnergyObserver : public SystemOf<Reads<Velocity<D>, Mass, Species>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<Velocity<D>, Mass, Species>, Writes<>>::View;
  static constexpr const char* observable = "kinetic_energy_by_species";
  explicit SpeciesKineticEnergyObserver(std::size_t species_count) : species_count_(species_count) {}

  std::string name() const override { return "observe_kinetic_energy_by_species"; }
  Access access() const override { return View::access().writes_observable(observable, unit::energy); }
  void run_on(View view) override {
    view.observables().set(observable, species_kinetic_energies<D>(view.template read<Velocity<D>>(),
                                                                   view.template read<Mass>(),
                                                                   view.template read<Species>(), species_count_));
  }

 private:
  std::size_t species_count_;
};

}  // namespace granflow
