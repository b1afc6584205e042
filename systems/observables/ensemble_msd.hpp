#pragma once
// The MSD of an ensemble of independent runs, as every MSD study reduces it:
// at each output time the mean over runs of the runs' particle-averaged MSD
// (MsdObserver, series "msd") with its standard error over runs; at each lag
// the mean over runs of the time-averaged MSD and of the ergodicity-breaking
// parameter (TimeAveragedMsdObserver), the former with its standard error.
// The diffusivity D(t) = dMSD/dt / 2d is derived from the mean and from the
// theory alike, so that the ballistic start enters both.

#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/core/sample_statistics.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/run/ensemble_keys.hpp"
#include "systems/observables/msd.hpp"
#include "systems/observables/time_averaged_msd.hpp"

namespace granflow {

struct EnsembleMsd {
  std::vector<double> time, msd, msd_stderr, msd_theory;
  std::vector<double> lag, time_averaged_msd, time_averaged_msd_stderr, ergodicity_breaking;
};

// `results.members[r].history`: what run r recorded. `time`: the times of
// the "msd" samples; `theory`: the MSD (all axes) at those times; `lag_time`:
// the time of one lag step of the time-averaged MSD (none recorded: no lags).
template <class Results>
EnsembleMsd reduce_ensemble_msd(const Results& results, std::vector<double> time, std::vector<double> theory,
                                double lag_time) {
  EnsembleMsd out;
  out.time = std::move(time);
  out.msd_theory = std::move(theory);
  for (std::size_t k = 0; k < out.time.size(); ++k) {
    const auto [mean, error] = mean_and_standard_error(member_values(results, "msd", k));
    out.msd.push_back(mean);
    out.msd_stderr.push_back(error);
  }
  const auto& history = results.members.front().history;
  if (!history.count("time_averaged_msd_lag")) return out;
  // The time average is published once, at the end of each run.
  const auto& lags = history.at("time_averaged_msd_lag").back().value;
  for (std::size_t k = 0; k < lags.size(); ++k) {
    const auto [mean, error] = mean_and_standard_error(member_values(results, "time_averaged_msd", 0, k));
    out.lag.push_back(lags[k] * lag_time);
    out.time_averaged_msd.push_back(mean);
    out.time_averaged_msd_stderr.push_back(error);
    out.ergodicity_breaking.push_back(mean_and_standard_error(member_values(results, "ergodicity_breaking", 0, k)).mean);
  }
  return out;
}

// The series of `r` into /observables; `step_of(k, t)`: the step recorded
// with the k-th time (or lag) t.
inline void write_ensemble_msd(H5mdFile& file, const EnsembleMsd& r, int dimension,
                               const std::function<std::int64_t(std::size_t, double)>& step_of) {
  const auto diffusivity = diffusivity_from_msd(r.time, r.msd, dimension);
  const auto diffusivity_theory = diffusivity_from_msd(r.time, r.msd_theory, dimension);
  declare_msd_series_units(file);
  for (std::size_t k = 0; k < r.time.size(); ++k) {
    const auto step = step_of(k, r.time[k]);
    file.append_observable("msd", step, r.time[k], r.msd[k]);
    file.append_observable("msd_stderr", step, r.time[k], r.msd_stderr[k]);
    file.append_observable("msd_theory", step, r.time[k], r.msd_theory[k]);
    file.append_observable("diffusivity", step, r.time[k], diffusivity[k]);
    file.append_observable("diffusivity_theory", step, r.time[k], diffusivity_theory[k]);
  }
  // Lags are stored as the `time` of these series.
  for (std::size_t k = 0; k < r.lag.size(); ++k) {
    const auto step = step_of(k, r.lag[k]);
    file.append_observable("time_averaged_msd", step, r.lag[k], r.time_averaged_msd[k]);
    file.append_observable("time_averaged_msd_stderr", step, r.lag[k], r.time_averaged_msd_stderr[k]);
    file.append_observable("ergodicity_breaking", step, r.lag[k], r.ergodicity_breaking[k]);
  }
}

// Largest |mean - theory| over the times, in standard errors of the mean.
inline double largest_deviation_in_standard_errors(const EnsembleMsd& r) {
  double worst = 0.0;
  for (std::size_t k = 0; k < r.time.size(); ++k)
    if (r.msd_stderr[k] > 0) worst = std::max(worst, std::abs(r.msd[k] - r.msd_theory[k]) / r.msd_stderr[k]);
  return worst;
}

}  // namespace granflow
