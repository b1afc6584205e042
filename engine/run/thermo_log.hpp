#pragma once
// A table of chosen scalar observables printed to standard error every N
// output rounds while a run goes on (as LAMMPS's thermo output does): step,
// time and each observable's latest value, the header again every 20 rows.
// `granflow run --log N [--log-observables a,b,...]`.

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/core/input_error.hpp"
#include "engine/core/suggestion.hpp"
#include "engine/run/observable_recorder.hpp"

namespace granflow {

class ThermoLog {
 public:
  // `names` empty: the first six scalar observables the run records, by
  // name, chosen at the first row (when their widths are known).
  ThermoLog(std::int64_t every, std::vector<std::string> names, const ObservableRecorder& recorder)
      : every_(every), names_(std::move(names)), recorder_(recorder) {
    const auto& recorded = recorder.observables();
    for (const auto& name : names_)
      if (std::find(recorded.begin(), recorded.end(), name) == recorded.end())
        throw InputError(fmt::format("--log-observables: this run records no observable '{}'{}", name,
                                     suggestion_text(name, recorded, "observables")));
  }

  // After each round of the run: a row when N output rounds have passed.
  void after_round(std::int64_t step, double time) {
    std::size_t samples = 0;
    for (const auto& [name, history] : recorder_.history()) samples += history.size();
    if (samples == samples_) return;  // no output this round
    samples_ = samples;
    if (++outputs_ % every_ != 0) return;
    if (names_.empty()) {
      std::vector<std::string> sorted = recorder_.observables();
      std::sort(sorted.begin(), sorted.end());
      for (const auto& name : sorted)
        if (names_.size() < 6 && recorder_.history().count(name) && !recorder_.vector_valued(name))
          names_.push_back(name);
    }
    if (rows_++ % 20 == 0) {
      std::string header = fmt::format("{:>14} {:>14}", "step", "time");
      for (const auto& name : names_) header += fmt::format(" {:>{}}", name, std::max<std::size_t>(14, name.size()));
      fmt::print(stderr, "{}\n", header);
    }
    std::string row = fmt::format("{:>14} {:>14.7g}", step, time);
    for (const auto& name : names_) {
      const auto history = recorder_.history().find(name);
      const auto width = std::max<std::size_t>(14, name.size());
      if (history == recorder_.history().end() || history->second.empty() || history->second.back().value.empty())
        row += fmt::format(" {:>{}}", "-", width);
      else
        row += fmt::format(" {:>{}.7g}", history->second.back().value.front(), width);
    }
    fmt::print(stderr, "{}\n", row);
  }

 private:
  std::int64_t every_;
  std::vector<std::string> names_;
  const ObservableRecorder& recorder_;
  std::size_t samples_ = 0;
  std::int64_t outputs_ = 0;
  std::int64_t rows_ = 0;
};

}  // namespace granflow
