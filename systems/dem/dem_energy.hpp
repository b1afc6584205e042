#pragma once
// The energy balance of the soft spheres: the work the moving walls did and
// the energy the dampers took, integrated over the run (trapezoidal rule
// over the instants the force pass books, second order in dt like the
// integrator), against the kinetic (with rotation), potential (-m g.x) and
// elastic energy:
//   E(t) - E(0) = energy_injected - energy_dissipated + O(dt^2).
// With friction the tangential springs' loss is booked per step from their
// stored energy before and after (first order where contacts slide).

#include <stdexcept>

#include "components/angular_velocity.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/core/observed_part.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/dem/contact_forces.hpp"

namespace granflow::dem {

inline const SystemDescription dem_energy_account_description{
    "dem_energy_account", "integrates the walls' power and the dampers' loss over each step"};
inline const SystemDescription observe_dem_energy_description{
    "observe_dem_energy", "kinetic, potential and elastic energy, energy injected and dissipated"};

struct DemLedger : Stateful {
  static constexpr const char* key = "dem_ledger";
  double injected = 0.0, dissipated = 0.0;
  double last_wall_power = 0.0, last_dissipation_power = 0.0;
  StateMap save_state() const override {
    return {{"ledger", {injected, dissipated, last_wall_power, last_dissipation_power}}};
  }
  // One step's trapezoid, from the powers the force pass booked at its end.
  void book(double dt, double wall_power, double dissipation_power) {
    injected += 0.5 * dt * (last_wall_power + wall_power);
    dissipated += 0.5 * dt * (last_dissipation_power + dissipation_power);
    last_wall_power = wall_power;
    last_dissipation_power = dissipation_power;
  }
  void restore_state(const StateMap& state) override {
    const auto& s = state.at("ledger");
    if (s.size() != 4) throw std::invalid_argument("checkpoint DEM energy ledger has the wrong size");
    injected = s[0];
    dissipated = s[1];
    last_wall_power = s[2];
    last_dissipation_power = s[3];
  }
};

// Every step, after the forces.
template <int D>
class DemEnergyAccount : public SystemOf<Reads<DemInteractions<D>>, Writes<DemLedger>> {
 public:
  using View = typename SystemOf<Reads<DemInteractions<D>>, Writes<DemLedger>>::View;
  explicit DemEnergyAccount(double dt) : dt_(dt) {}
  std::string name() const override { return "dem_energy_account"; }
  void run_on(View view) override {
    const auto& in = view.template read<DemInteractions<D>>();
    view.template write<DemLedger>().book(dt_, in.wall_power, in.dissipation_power);
  }

 private:
  double dt_;
};

template <int D>
using DemEnergyObserverBase =
    SystemOf<Reads<Position<D>, Velocity<D>, AngularVelocity, Radius, Mass, DemInteractions<D>, DemLedger>, Writes<>>;

template <int D>
class DemEnergyObserver : public DemEnergyObserverBase<D> {
 public:
  using View = typename DemEnergyObserverBase<D>::View;
  std::string name() const override { return "observe_dem_energy"; }
  // The spheres' sums in the whole system's grouping; the contacts' terms
  // are the whole's on every rank.
  bool observes_by_rank() const override { return true; }
  Access access() const override {
    return View::access()
        .writes_observable("kinetic_energy", unit::energy)
        .writes_observable("potential_energy", unit::energy)
        .writes_observable("elastic_energy", unit::energy)
        .writes_observable("energy_injected", unit::energy)
        .writes_observable("energy_dissipated", unit::energy)
        .writes_observable("contact_count", unit::none)
        .writes_observable("coordination_number", unit::none);
  }
  void run_on(View view) override {
    const auto& x = view.template read<Position<D>>();
    const auto& v = view.template read<Velocity<D>>();
    const auto& m = view.template read<Mass>();
    const auto& in = view.template read<DemInteractions<D>>();
    const auto& ledger = view.template read<DemLedger>();
    const std::size_t n = view.size();
    auto& store = view.observables();
    // With friction the spheres rotate: I w^2 / 2 with I = (2/5) m r^2.
    const Vec<3>* w =
        view.template has<AngularVelocity>() ? view.template read<AngularVelocity>().values.data() : nullptr;
    const auto& r = view.template read<Radius>();
    const ObservedPart& part = view.part();
    store.set("kinetic_energy", 0.5 * part.sum(n, [&](std::size_t i) {
                return m[i] * v[i].squaredNorm() + (w ? 0.4 * m[i] * r[i] * r[i] * w[i].squaredNorm() : 0.0);
              }));
    store.set("potential_energy", -part.sum(n, [&](std::size_t i) {
                double h = 0.0;
                for (int a = 0; a < D; ++a) h += in.gravity[a] * x[i][a];
                return m[i] * h;
              }));
    store.set("elastic_energy", in.elastic);
    store.set("energy_injected", ledger.injected);
    store.set("energy_dissipated", ledger.dissipated);
    store.set("contact_count", static_cast<double>(in.contacts));
    const double spheres = part.total(static_cast<double>(n));
    store.set("coordination_number", spheres > 0 ? 2.0 * static_cast<double>(in.contacts) / spheres : 0.0);
  }
};

}  // namespace granflow::dem
