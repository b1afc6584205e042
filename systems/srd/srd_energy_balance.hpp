#pragma once
// The energy balance of a driven SRD run, added as one piece: the ledger of
// what the walls inject, the collisions dissipate and the ghost cells
// exchange (booked every step, kept in checkpoints as "energy"), written at
// every output beside the kinetic and potential energy, and watched there
// (srd_watchdog.hpp); its totals are logged when the run ends.

#include <spdlog/spdlog.h>

#include <array>
#include <memory>

#include "engine/core/trigger.hpp"
#include "engine/run/run.hpp"
#include "systems/srd/srd_energy.hpp"
#include "systems/srd/srd_watchdog.hpp"

namespace granflow::srd {

// `g`: the body force per mass (its potential energy is part of the balance).
template <int D>
void add_energy_balance(Run& run, const TriggerPtr& outputs, const std::array<double, D>& g) {
  const auto ledger = std::make_shared<EnergyLedger>();
  run.keep("energy", *ledger);
  run.observe<SrdEnergyAccount<D>>(std::make_shared<EverySteps>(1, 1), ledger);
  run.observe<SrdEnergyObserver<D>>(outputs, ledger, g);
  run.observe<SrdEnergyWatch>(outputs);
  run.at_finish([ledger](H5mdFile&, const RunOutcome&) {
    spdlog::info("energy: injected by the floor {:.6g}, dissipated {:.6g}, exchanged in ghost cells {:.6g}",
                 ledger->injected, ledger->dissipated, ledger->ghost_exchange);
  });
}

}  // namespace granflow::srd
