#pragma once
// The physics watchdog of a soft-sphere run, as the event-driven gas has its
// collapse monitor: it stops the run (exit 3) with a diagnosis when the
// integration has failed, rather than let it write a file of nonsense.
//  - At every neighbour-list build, in the pass that bins the spheres (no
//    pass of its own): a position that is not finite, or a centre beyond
//    the farthest reach of the walls along a closed axis (a sphere through
//    a wall). Either forces a build within a few steps: an escaped sphere
//    keeps moving away from the wall that pushes it, and a position that is
//    not finite counts as moved beyond the skin (neighbour_list.hpp).
//  - At every output: the energy ledger (dem_energy.hpp). E(t) - E(0) must
//    equal what the walls injected less what the contacts dissipated up to
//    the integrator's O(dt^2); an unstable step creates energy, and a
//    difference beyond a quarter of the energy turned over stops the run.
// The diagnosis says what failed, when, and which time scale the step must
// resolve.

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "components/clock.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/run/run_control.hpp"

namespace granflow::dem {

inline const SystemDescription watch_dem_energy_description{
    "watch_dem_energy", "stops the run when the energy ledger no longer balances (an unstable step)"};

// What the checks compare with, set before the run.
template <int D>
struct DemWatch {
  static constexpr const char* key = "dem_watch";
  // Along each closed axis the farthest the walls reach; +-infinity along periodic ones.
  std::array<double, D> lower{}, upper{};
  // What to change, appended to every diagnosis.
  std::string advice;
};

// Stops the run with `what` (at the clock's time) and the advice.
template <int D>
void fail_run(View<Reads<Clock, DemWatch<D>>, Writes<RunControl>> view, const std::string& what) {
  const auto& clock = view.template read<Clock>();
  view.template write<RunControl>().fail(
      fmt::format("the soft-sphere integration failed at t = {:.6g} (step {}): {}. {}", clock.time, clock.step, what,
                  view.template read<DemWatch<D>>().advice));
}

// A sphere beyond the walls' reach or not finite: which, along which axis,
// where.
struct EscapedSphere {
  std::uint64_t sphere = 0;
  int axis = 0;
  double position = 0.0;
};

// The first of spheres [from, to) that escaped, if one did.
template <int D>
std::optional<EscapedSphere> first_escaped(const Position<D>& x, const ParticleId* id, const DemWatch<D>& watch,
                                           std::size_t from, std::size_t to) {
  for (std::size_t i = from; i < to; ++i)
    for (int a = 0; a < D; ++a) {
      const double p = x[i][a];
      if (p >= watch.lower[a] && p <= watch.upper[a]) continue;
      return EscapedSphere{id ? (*id)[i] : i, a, p};
    }
  return std::nullopt;
}

template <int D>
std::string escape_diagnosis(const EscapedSphere& e, const DemWatch<D>& watch) {
  constexpr const char* axis_name[] = {"x", "y", "z"};
  if (!std::isfinite(e.position))
    return fmt::format("sphere {} has a position that is not finite ({} = {})", e.sphere, axis_name[e.axis], e.position);
  return fmt::format("sphere {} went through a wall: {} = {:.6g}, outside the walls' reach [{:.6g}, {:.6g}]", e.sphere,
                     axis_name[e.axis], e.position, watch.lower[e.axis], watch.upper[e.axis]);
}

// Called when the drift found a sphere out of bounds: names the first one.
template <int D>
void report_escaped_sphere(View<Reads<Clock, DemWatch<D>, Position<D>, ParticleId>, Writes<RunControl>> view) {
  const auto& watch = view.template read<DemWatch<D>>();
  const auto* id = view.template has<ParticleId>() ? &view.template read<ParticleId>() : nullptr;
  if (const auto e = first_escaped<D>(view.template read<Position<D>>(), id, watch, 0, view.size()))
    fail_run<D>(view, escape_diagnosis<D>(*e, watch));
}

// The energy balance at every output, after observe_dem_energy.
template <int D>
class DemEnergyWatch : public SystemOf<Reads<Clock, DemWatch<D>>, Writes<RunControl>>, public Stateful {
 public:
  using View = typename SystemOf<Reads<Clock, DemWatch<D>>, Writes<RunControl>>::View;
  static constexpr double tolerance = 0.25;  // of the energy turned over
  std::string name() const override { return "watch_dem_energy"; }
  // It reads the observables, which are the whole system's on every rank.
  bool observes_by_rank() const override { return true; }
  Access access() const override {
    return View::access()
        .reads_observable("kinetic_energy")
        .reads_observable("potential_energy")
        .reads_observable("elastic_energy")
        .reads_observable("energy_injected")
        .reads_observable("energy_dissipated");
  }
  void run_on(View view) override {
    auto& store = view.observables();
    const double kinetic = store.scalar("kinetic_energy"), potential = store.scalar("potential_energy");
    const double elastic = store.scalar("elastic_energy"), injected = store.scalar("energy_injected");
    const double dissipated = store.scalar("energy_dissipated");
    const double energy = kinetic + potential + elastic;
    if (!std::isfinite(energy) || !std::isfinite(injected) || !std::isfinite(dissipated))
      return fail_run<D>(view, fmt::format("the energy is not finite (kinetic {}, potential {}, elastic {})", kinetic,
                                            potential, elastic));
    if (!started_) {
      started_ = true;
      start_ = {kinetic + elastic, potential};
      return;
    }
    const double error = std::abs(energy - start_[0] - start_[1] - (injected - dissipated));
    const double turnover = kinetic + elastic + start_[0] + std::abs(potential - start_[1]) + injected + dissipated;
    if (error > tolerance * turnover)
      fail_run<D>(view, fmt::format("the energy changed by {:.4g} since the start, but the walls injected {:.4g} and "
                                     "the contacts dissipated {:.4g}: the step created {:.4g} ({:.0f} % of the energy "
                                     "turned over)",
                                     energy - start_[0] - start_[1], injected, dissipated,
                                     energy - start_[0] - start_[1] - (injected - dissipated),
                                     100.0 * error / turnover));
  }
  StateMap save_state() const override { return {{"start", {started_ ? 1.0 : 0.0, start_[0], start_[1]}}}; }
  void restore_state(const StateMap& state) override {
    const auto& s = state.at("start");
    if (s.size() != 3) throw std::invalid_argument("checkpoint energy watch has the wrong size");
    started_ = s[0] != 0.0;
    start_ = {s[1], s[2]};
  }

 private:
  bool started_ = false;
  std::array<double, 2> start_{};  // kinetic + elastic, potential
};

}  // namespace granflow::dem
