#pragma once
// The reduction of an ensemble whose runs record the same series at the same
// times: every observable becomes its mean over the runs, with the standard
// error of that mean beside it as <name>_stderr (component by component for
// vector-valued ones), and every derived quantity its mean over the runs.
// Samples are matched by time; the step stored is the first run's (event-driven
// runs reach one time after different numbers of rounds).
// The runs' scatter, not a model of it, is the error bar: the samples of one
// run are correlated in time, the runs are independent.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/core/sample_statistics.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/run/scenario.hpp"

namespace granflow {

// How many leading samples of `name` every member recorded at the same time
// (a run stopped early by its own stop criterion records fewer).
inline std::size_t common_samples(const EnsembleResults& results, const std::string& name) {
  const auto& first = results.members.front().history.at(name);
  std::size_t count = first.size();
  for (const auto& member : results.members) {
    const auto it = member.history.find(name);
    if (it == member.history.end()) return 0;
    const auto& samples = it->second;
    std::size_t k = 0;
    while (k < std::min(count, samples.size()) && samples[k].value.size() == first[k].value.size() &&
           std::abs(samples[k].time - first[k].time) <= 1e-12 * std::max(1.0, std::abs(first[k].time)))
      ++k;
    count = k;
  }
  return count;
}

inline void write_ensemble_series(const EnsembleResults& results, H5mdFile& file) {
  const auto& members = results.members;
  if (members.empty()) return;
  for (const auto& [name, unit] : members.front().units) {
    file.declare_unit(name, unit);
    file.declare_unit(name + "_stderr", unit);
  }
  for (const auto& [name, first] : members.front().history) {
    const std::size_t count = common_samples(results, name);
    if (count < first.size())
      spdlog::warn("{}: {} of {} samples are common to all {} runs; the rest is left out", name, count, first.size(),
                   members.size());
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t width = first[k].value.size();
      std::vector<double> mean(width), error(width), samples(members.size());
      for (std::size_t c = 0; c < width; ++c) {
        for (std::size_t r = 0; r < members.size(); ++r) samples[r] = members[r].history.at(name)[k].value[c];
        const auto [m, e] = mean_and_standard_error(samples);
        mean[c] = m;
        error[c] = e;
      }
      if (width == 1) {
        file.append_observable(name, first[k].step, first[k].time, mean.front());
        file.append_observable(name + "_stderr", first[k].step, first[k].time, error.front());
      } else {
        file.append_observable(name, first[k].step, first[k].time, mean);
        file.append_observable(name + "_stderr", first[k].step, first[k].time, error);
      }
    }
  }
  for (const auto& [name, value] : members.front().derived) {
    std::vector<double> samples;
    for (const auto& member : members)
      if (const auto it = member.derived.find(name); it != member.derived.end()) samples.push_back(it->second);
    file.write_attribute("/parameters/derived", name, mean_and_standard_error(samples).mean);
  }
  file.write_attribute("/observables", "runs", static_cast<double>(members.size()));
}

}  // namespace granflow
