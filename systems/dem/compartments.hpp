#pragma once
// Two compartments split by a divider at x = position along `axis`: the
// asymmetry a = (N_L - N_R) / N of the spheres on each side, and the
// spheres that crossed from left to right and back. A sampler looks every
// step (a crossing takes many steps, so none is missed) and the observer
// writes the crossings since its last output, and keeps the time averages
// of a and |a| over the outputs after a warm-up (the sweep's summary).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <stdexcept>
#include <vector>

#include "components/clock.hpp"
#include "components/compartment_side.hpp"
#include "components/position.hpp"
#include "engine/core/config.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/run/run.hpp"
#include "systems/observables/least_squares.hpp"

namespace granflow::dem {

inline const SystemDescription sample_compartments_description{
    "sample_compartments", "which compartment every sphere is in, and the crossings since the last step"};
inline const SystemDescription observe_compartments_description{
    "observe_compartments", "asymmetry (N_L - N_R) / N and the flux through the opening in each direction"};

// Eggers' flux model F(n) = A n^2 exp(-B n^2) (Eggers 1999) fitted to the
// crossings out of a compartment per interval against its fraction n at the
// interval's start: the samples binned in n (`bins` over [0, 1]), each bin's
// mean flux, then log(F / n^2) = log A - B n^2 by least squares over the
// bins with flux, weighted by their samples. The equal sharing n = 1/2 is
// stable for B < 4. Returns {A, B}, or {0, 0} with fewer than three bins.
inline std::array<double, 2> fit_eggers_flux(const std::vector<double>& samples, int bins = 20) {
  std::vector<double> flux(static_cast<std::size_t>(bins), 0.0), count(static_cast<std::size_t>(bins), 0.0),
      fraction(static_cast<std::size_t>(bins), 0.0);
  for (std::size_t k = 0; k + 1 < samples.size(); k += 2) {
    const auto b = static_cast<std::size_t>(std::min(bins - 1, static_cast<int>(samples[k] * bins)));
    fraction[b] += samples[k];
    flux[b] += samples[k + 1];
    count[b] += 1.0;
  }
  LineFit fit;
  for (std::size_t b = 0; b < flux.size(); ++b) {
    if (count[b] == 0 || flux[b] == 0) continue;
    const double n = fraction[b] / count[b], f = flux[b] / count[b];
    fit.add(n * n, std::log(f / (n * n)), count[b]);
  }
  if (fit.points() < 3 || fit.determinant() <= 0) return {0.0, 0.0};
  const double slope = fit.slope(), intercept = fit.intercept();
  return {std::exp(intercept), -slope};
}

class CompartmentCounts : public Stateful {
 public:
  static constexpr const char* key = "dem_compartments";
  double left_to_right = 0.0, right_to_left = 0.0;  // since the last output
  // Over the outputs from `average_from` on: sums of a and |a|, their count,
  // and all crossings.
  double average_from = 0.0;
  double sum = 0.0, abs_sum = 0.0, samples = 0.0, crossings = 0.0;
  // Per output interval after average_from, for each compartment: the
  // fraction of the spheres in it at the interval's start and how many left
  // it during the interval (Eggers' flux function F(n)).
  std::vector<double> flux_samples;  // (n, crossings out) pairs
  double last_left_fraction = -1.0;

  StateMap save_state() const override {
    return {{"flux", {left_to_right, right_to_left}},
            {"averages", {sum, abs_sum, samples, crossings, last_left_fraction}},
            {"flux_samples", flux_samples}};
  }
  void restore_state(const StateMap& state) override {
    if (state.at("flux").size() != 2 || state.at("averages").size() != 5)
      throw std::invalid_argument("checkpoint compartment counts have the wrong size");
    left_to_right = state.at("flux")[0];
    right_to_left = state.at("flux")[1];
    sum = state.at("averages")[0];
    abs_sum = state.at("averages")[1];
    samples = state.at("averages")[2];
    crossings = state.at("averages")[3];
    last_left_fraction = state.at("averages")[4];
    flux_samples = state.at("flux_samples");
  }
};

// Each sphere's side now against the side it was on at the last step
// (CompartmentSide), every step. Over ranks each rank looks at its own
// spheres, and the step's crossings are added over the ranks (exact
// counts), so every rank keeps the whole system's.
template <int D>
class CompartmentSampler : public SystemOf<Reads<Position<D>>, Writes<CompartmentSide, CompartmentCounts>> {
 public:
  using View = typename SystemOf<Reads<Position<D>>, Writes<CompartmentSide, CompartmentCounts>>::View;
  CompartmentSampler(int axis, double position, std::shared_ptr<CompartmentCounts> counts)
      : axis_(axis), position_(position), counts_(std::move(counts)) {}
  std::string name() const override { return "sample_compartments"; }
  bool observes_by_rank() const override { return true; }
  void run_on(View view) override {
    const auto& x = view.template read<Position<D>>();
    auto& side = view.template write<CompartmentSide>();
    double to_right = 0.0, to_left = 0.0;
    for (std::size_t i = 0; i < view.size(); ++i) {
      const std::uint8_t now = x[i][axis_] < position_ ? left : right;
      if (side[i] == left && now == right) to_right += 1.0;
      if (side[i] == right && now == left) to_left += 1.0;
      side[i] = now;
    }
    const std::vector<double> crossed = view.part().total(std::vector<double>{to_right, to_left});
    counts_->left_to_right += crossed[0];
    counts_->right_to_left += crossed[1];
  }

 private:
  static constexpr std::uint8_t left = 1, right = 2;
  int axis_;
  double position_;
  std::shared_ptr<CompartmentCounts> counts_;
};

template <int D>
class CompartmentObserver : public SystemOf<Reads<Position<D>, Clock>, Writes<CompartmentCounts>> {
 public:
  using View = typename SystemOf<Reads<Position<D>, Clock>, Writes<CompartmentCounts>>::View;
  CompartmentObserver(int axis, double position, std::shared_ptr<CompartmentCounts> counts)
      : axis_(axis), position_(position), counts_(std::move(counts)) {}
  std::string name() const override { return "observe_compartments"; }
  Access access() const override {
    return View::access()
        .writes_observable("asymmetry", unit::none)
        .writes_observable("flux_left_to_right", unit::none)
        .writes_observable("flux_right_to_left", unit::none);
  }
  // Counts of spheres, exact whatever the ranks add.
  bool observes_by_rank() const override { return true; }
  void run_on(View view) override {
    const auto& x = view.template read<Position<D>>();
    double own_left = 0.0;
    for (std::size_t i = 0; i < view.size(); ++i) own_left += x[i][axis_] < position_ ? 1.0 : 0.0;
    const std::vector<double> totals =
        view.part().total(std::vector<double>{own_left, static_cast<double>(view.size())});
    const double left = totals[0], n = totals[1];
    const double a = n > 0 ? (2.0 * left - n) / n : 0.0;
    auto& c = *counts_;
    c.crossings += c.left_to_right + c.right_to_left;
    if (view.template read<Clock>().time >= c.average_from) {
      c.sum += a;
      c.abs_sum += std::abs(a);
      c.samples += 1.0;
      if (c.last_left_fraction >= 0.0) {
        c.flux_samples.insert(c.flux_samples.end(), {c.last_left_fraction, c.left_to_right});
        c.flux_samples.insert(c.flux_samples.end(), {1.0 - c.last_left_fraction, c.right_to_left});
      }
      c.last_left_fraction = n > 0 ? left / n : 0.0;
    }
    auto& store = view.observables();
    store.set("asymmetry", a);
    store.set("flux_left_to_right", counts_->left_to_right);
    store.set("flux_right_to_left", counts_->right_to_left);
    counts_->left_to_right = 0.0;
    counts_->right_to_left = 0.0;
  }

 private:
  int axis_;
  double position_;
  std::shared_ptr<CompartmentCounts> counts_;
};

// The compartments left and right of a divider at x = `divider_x`: sampled
// every step, written at every output (CompartmentObserver), their
// asymmetry and flux averaged from `average_from` on and summarised when the
// run ends (asymmetry_time_mean, asymmetry_abs_mean, crossings, Eggers'
// flux fit eggers_flux_A and eggers_flux_B). Kept in checkpoints as
// "compartments".
template <int D>
void add_compartments(Run& run, const TriggerPtr& outputs, double divider_x, double average_from) {
  const double t_stop = run.config().real("run.t_stop");
  if (average_from >= t_stop)
    throw ConfigError(fmt::format("output.average_after = {} leaves nothing to average before run.t_stop = {}",
                                  average_from, t_stop));
  const auto counts = std::make_shared<CompartmentCounts>();
  counts->average_from = average_from;
  run.keep("compartments", *counts);
  // A resumed run has the sides from its checkpoint.
  if (!run.world().has_component<CompartmentSide>()) run.world().add_component<CompartmentSide>();
  run.observe<CompartmentSampler<D>>(std::make_shared<EverySteps>(1), 0, divider_x, counts);
  run.observe<CompartmentObserver<D>>(outputs, 0, divider_x, counts);
  run.at_finish([counts](H5mdFile& file, const RunOutcome&) {
    const double samples = std::max(counts->samples, 1.0);
    file.write_attribute("/observables", "asymmetry_time_mean", counts->sum / samples);
    file.write_attribute("/observables", "asymmetry_abs_mean", counts->abs_sum / samples);
    file.write_attribute("/observables", "crossings", counts->crossings);
    const auto eggers = fit_eggers_flux(counts->flux_samples);
    file.write_attribute("/observables", "eggers_flux_A", eggers[0]);
    file.write_attribute("/observables", "eggers_flux_B", eggers[1]);
    spdlog::info("time average after the warm-up ({:.0f} outputs): a = {:.3f}, |a| = {:.3f}; {:.0f} crossings; {}",
                 counts->samples, counts->sum / samples, counts->abs_sum / samples, counts->crossings,
                 eggers[1] != 0.0 ? fmt::format("Eggers flux fit A = {:.3g}, B = {:.3g} (equal sharing is stable for "
                                                "B < 4)", eggers[0], eggers[1])
                                  : std::string("too few crossings to fit Eggers' flux model"));
  });
}

}  // namespace granflow::dem
