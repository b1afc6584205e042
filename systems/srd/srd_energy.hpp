#pragma once
// The energy balance of an SRD fluid between walls under a body force:
// what the moving walls give (energy_injected), what the collisions take in
// cells without ghost particles (energy_dissipated: the granular loss) and
// what they change in cells with them (energy_ghost_exchange: loss and the
// heat the ghosts at the wall temperature exchange), summed over the run,
// against the fluid's kinetic and potential energy. Nothing else changes the
// energy (the streaming under a constant force is exact), so
//   E(t) - E(0) = energy_injected - energy_dissipated + energy_ghost_exchange
// to round-off; energy_balance_error is the difference. A global thermostat
// changes the energy outside this ledger, and the potential energy counts
// only the force's components along walled axes (a periodic axis has no
// height to count it from), so the balance holds without a thermostat and
// with the force along walled axes, acting everywhere.

#include <array>
#include <memory>
#include <stdexcept>

#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/deterministic_sum.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription account_srd_energy_description{
    "account_srd_energy", "adds each step's wall work and collision energy change to the run's energy ledger"};
inline const SystemDescription observe_srd_energy_description{
    "observe_srd_energy", "kinetic and potential energy, energy injected by walls, dissipated, exchanged with ghosts"};

class EnergyLedger : public Stateful {
 public:
  // Shared by the account and the observer (not a World resource): the key
  // of their access declarations, which orders them.
  static constexpr const char* key = "srd_energy_ledger";
  double injected = 0.0;
  double dissipated = 0.0;
  double ghost_exchange = 0.0;
  double initial = 0.0;  // E(0), set by the first observation
  bool has_initial = false;

  StateMap save_state() const override {
    return {{"sums", {injected, dissipated, ghost_exchange, initial, has_initial ? 1.0 : 0.0}}};
  }
  void restore_state(const StateMap& state) override {
    const auto& s = state.at("sums");
    if (s.size() != 5) throw std::invalid_argument("checkpoint energy ledger has the wrong size");
    injected = s[0];
    dissipated = s[1];
    ghost_exchange = s[2];
    initial = s[3];
    has_initial = s[4] != 0.0;
  }
};

// Every step, after the rotation.
template <int D>
class SrdEnergyAccount : public SystemOf<Reads<SrdCells<D>>, Writes<EnergyLedger>> {
 public:
  using View = typename SystemOf<Reads<SrdCells<D>>, Writes<EnergyLedger>>::View;
  explicit SrdEnergyAccount(std::shared_ptr<EnergyLedger> ledger) : ledger_(std::move(ledger)) {}
  std::string name() const override { return "account_srd_energy"; }
  // The step's energies are set on the host every step, wherever the step runs.
  bool reads_device_state(const World&) const override { return false; }
  // The step's energies are the totals over the ranks, on every rank.
  bool observes_by_rank() const override { return true; }
  void run_on(View view) override {
    const auto& cells = view.template read<SrdCells<D>>();
    if (!cells.record_energy) throw std::logic_error("account_srd_energy needs SrdCells::record_energy");
    ledger_->injected += cells.step_wall_work;
    ledger_->dissipated -= cells.step_collision_energy;
    ledger_->ghost_exchange += cells.step_ghost_cell_energy;
  }

 private:
  std::shared_ptr<EnergyLedger> ledger_;
};

template <int D>
class SrdEnergyObserver : public SystemOf<Reads<Position<D>, Velocity<D>, SrdCells<D>>, Writes<EnergyLedger>> {
 public:
  using View = typename SystemOf<Reads<Position<D>, Velocity<D>, SrdCells<D>>, Writes<EnergyLedger>>::View;
  // acceleration: the body force per mass whose potential is counted.
  SrdEnergyObserver(std::shared_ptr<EnergyLedger> ledger, std::array<double, D> acceleration)
      : ledger_(std::move(ledger)), acceleration_(acceleration) {}
  std::string name() const override { return "observe_srd_energy"; }
  Access access() const override {
    return View::access()
        .writes_observable("kinetic_energy", unit::energy)
        .writes_observable("potential_energy", unit::energy)
        .writes_observable("energy_injected", unit::energy)
        .writes_observable("energy_dissipated", unit::energy)
        .writes_observable("energy_ghost_exchange", unit::energy)
        .writes_observable("energy_balance_error", unit::energy);
  }
  // Each rank sums its own particles' energies; the ledger is the same on every rank.
  bool observes_by_rank() const override { return true; }
  void run_on(View view) override {
    const auto& cells = view.template read<SrdCells<D>>();
    const auto& x = view.template read<Position<D>>();
    const auto& v = view.template read<Velocity<D>>();
    const double m = cells.particle_mass;
    const double kinetic =
        0.5 * m * view.part().total(deterministic_sum(view.size(), [&](std::size_t i) { return v[i].squaredNorm(); }));
    double g[D];
    // Along walled axes: a rank's part of the grid also ends along its
    // slab's axis, which is periodic.
    for (int a = 0; a < D; ++a)
      g[a] = cells.bounded & (1u << a) && a != cells.part_of_whole.axis ? acceleration_[a] : 0.0;
    const double potential = -m * view.part().total(deterministic_sum(view.size(), [&](std::size_t i) {
      double h = 0.0;
      for (int a = 0; a < D; ++a) h += g[a] * x[i][a];
      return h;
    }));
    if (!ledger_->has_initial) {
      ledger_->initial = kinetic + potential;
      ledger_->has_initial = true;
    }
    auto& store = view.observables();
    store.set("kinetic_energy", kinetic);
    store.set("potential_energy", potential);
    store.set("energy_injected", ledger_->injected);
    store.set("energy_dissipated", ledger_->dissipated);
    store.set("energy_ghost_exchange", ledger_->ghost_exchange);
    store.set("energy_balance_error", kinetic + potential - ledger_->initial -
                                          (ledger_->injected - ledger_->dissipated + ledger_->ghost_exchange));
  }

 private:
  std::shared_ptr<EnergyLedger> ledger_;
  std::array<double, D> acceleration_;
};

}  // namespace granflow::srd
