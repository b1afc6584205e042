#pragma once
// The physics watchdog of an SRD run: it stops the run (exit 3) with a
// diagnosis instead of letting it write a file of nonsense.
//  - Every step, the streaming itself: a particle that needs more wall
//    reflections in one step than it may have (streaming.hpp).
//  - At every output, from what the observers computed anyway (no pass of
//    its own): a temperature that is not finite (a velocity blew up), and,
//    where the run keeps an energy ledger, a balance that no longer holds.
//    The ledger is exact up to round-off (srd_energy.hpp), so a difference
//    beyond 1e-6 of the energy turned over means energy went unbooked.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "components/clock.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/run/observable_recorder.hpp"
#include "engine/run/run.hpp"
#include "engine/run/run_control.hpp"
#include "systems/srd/srd_cells.hpp"
#include "systems/srd/srd_setup.hpp"
#include "systems/srd/srd_state_observer.hpp"

namespace granflow::srd {

inline const SystemDescription watch_srd_state_description{
    "watch_srd_state", "stops the run when the fluid's temperature is no longer finite"};
inline const SystemDescription watch_srd_energy_description{
    "watch_srd_energy", "stops the run when the energy ledger no longer balances to round-off"};

using SrdWatchView = View<Reads<Clock>, Writes<RunControl>>;

inline void fail_srd_run(SrdWatchView view, const std::string& what) {
  const auto& clock = view.read<Clock>();
  view.write<RunControl>().fail(
      fmt::format("the SRD run failed at t = {:.6g} (step {}): {}", clock.time, clock.step, what));
}

inline double observed(const SrdWatchView& view, const char* name) { return view.observables().scalar(name); }

class SrdStateWatch : public SystemOf<Reads<Clock>, Writes<RunControl>> {
 public:
  std::string name() const override { return "watch_srd_state"; }
  bool observes_by_rank() const override { return true; }  // the observables are the totals
  Access access() const override {
    return View::access()
        .reads_observable("temperature")
        .reads_observable("granular_temperature");
  }
  void run_on(View view) override {
    const double temperature = observed(view, "temperature"), granular = observed(view, "granular_temperature");
    if (!std::isfinite(temperature) || !std::isfinite(granular))
      fail_srd_run(view, fmt::format("the fluid's temperature is not finite (thermal {}, granular {}): a velocity "
                                      "blew up; check srd.time_step, the force and the walls' motion",
                                      temperature, granular));
  }
};

class SrdEnergyWatch : public SystemOf<Reads<Clock>, Writes<RunControl>> {
 public:
  static constexpr double tolerance = 1e-6;  // of the energy turned over
  std::string name() const override { return "watch_srd_energy"; }
  bool observes_by_rank() const override { return true; }
  Access access() const override {
    return View::access()
        .reads_observable("kinetic_energy")
        .reads_observable("potential_energy")
        .reads_observable("energy_injected")
        .reads_observable("energy_dissipated")
        .reads_observable("energy_ghost_exchange")
        .reads_observable("energy_balance_error");
  }
  void run_on(View view) override {
    const double error = observed(view, "energy_balance_error");
    const double turnover = observed(view, "kinetic_energy") + std::abs(observed(view, "potential_energy")) +
                            observed(view, "energy_injected") + std::abs(observed(view, "energy_dissipated")) +
                            std::abs(observed(view, "energy_ghost_exchange"));
    if (!std::isfinite(error) || std::abs(error) > tolerance * turnover)
      fail_srd_run(view, fmt::format("the energy ledger is off by {:.4g} ({:.2g} of the {:.4g} turned over), far "
                                      "beyond round-off: energy changed that no wall, collision or ghost booked; "
                                      "lower srd.time_step or the force",
                                      error, std::abs(error) / turnover, turnover));
  }
};

// The state observables at `when`, watched.
template <int D>
void observe_state(Run& run, const TriggerPtr& when) {
  run.observe<SrdStateObserver<D>>(when, granular_parameters(rotation_from(run.config())));
  run.observe<SrdStateWatch>(when);
}

// Granular SRD is very compressible: the dense layer's pattern can coarsen
// into one spot. Not a failure of the method, so a warning when the run ends,
// once a cell held more than 20 times the mean `n0` at the last output
// (peak_cell_density, srd_height_observer.hpp, observed by rank).
inline void warn_when_collapsed(Run& run, double n0) {
  run.at_finish([&run, n0](H5mdFile&, const RunOutcome&) {
    const auto& history = run.recorder().history();
    const auto peaks = history.find("peak_cell_density");
    if (peaks == history.end() || peaks->second.empty()) return;
    const double peak = peaks->second.back().value.at(0);
    if (peak > 20.0)
      spdlog::warn("the fluid has collapsed: one cell holds {:.0f} particles, {:.0f} times the mean; granular SRD's "
                   "compressibility lets the dense layer's pattern coarsen into one spot",
                   peak * n0, peak);
  });
}

// Compiled once for both dimensions, in srd_watchdog.cpp, for every SRD scenario.
extern template void observe_state<2>(Run&, const TriggerPtr&);
extern template void observe_state<3>(Run&, const TriggerPtr&);

}  // namespace granflow::srd
