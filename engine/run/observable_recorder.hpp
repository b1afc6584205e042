#pragma once
// Appends every fresh observable to /observables/<name>/{step,time,value}
// and keeps what it wrote, so a checkpoint carries the series and a resumed
// run writes them again into its new result file. The Runner adds it after
// every observer, reading every observable they declare.

#include <algorithm>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "components/clock.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/run/output_file.hpp"

namespace granflow {

inline const SystemDescription write_observables_description{"write_observables", "appends fresh observables to /observables/<name>/{step,time,value}"};

struct ObservableSample {
  std::int64_t step;
  double time;
  std::vector<double> value;
};
using ObservableHistory = std::map<std::string, std::vector<ObservableSample>>;

// A history as flat arrays (<name>/step, /time, /value, /width) and back.
StateMap save_history(const ObservableHistory& history);
ObservableHistory load_history(const StateMap& saved);

class ObservableRecorder : public SystemOf<Reads<Clock>, Writes<OutputFile>> {
 public:
  explicit ObservableRecorder(std::vector<std::string> observables) : observables_(std::move(observables)) {}

  std::string name() const override { return "write_observables"; }
  Access access() const override {
    // It clears each slot's `fresh` flag, so it writes the observables it records.
    Access access = View::access();
    for (const auto& name : observables_) access.writes_observable(name);
    return access;
  }
  void run_on(View view) override {
    const auto& clock = view.read<Clock>();
    auto& store = view.observables();
    H5mdFile* file = view.write<OutputFile>().file;
    for (const auto& name : observables_) {
      auto& slot = store.slot(name);
      if (!slot.fresh) continue;
      append(file, name, {clock.step, clock.time, slot.value});
      slot.fresh = false;
    }
    if (file) file->flush_if_due();
  }

  void append(H5mdFile* file, const std::string& name, const ObservableSample& sample) {
    if (file) {
      if (sample.value.size() == 1)
        file->append_observable(name, sample.step, sample.time, sample.value.front());
      else
        file->append_observable(name, sample.step, sample.time, sample.value);
    }
    history_[name].push_back(sample);
  }
  const ObservableHistory& history() const { return history_; }
  const std::vector<std::string>& observables() const { return observables_; }
  // Whether the observable's samples so far hold more than one value.
  bool vector_valued(const std::string& name) const {
    const auto it = history_.find(name);
    return it != history_.end() && !it->second.empty() && it->second.back().value.size() > 1;
  }

  using SeriesLengths = std::map<std::string, std::size_t>;
  SeriesLengths lengths() const {
    SeriesLengths out;
    for (const auto& [name, samples] : history_) out[name] = samples.size();
    return out;
  }
  StateMap save_history() const { return granflow::save_history(history_); }
  // The samples each series held at `lengths` (a series absent there had none).
  StateMap save_history(const SeriesLengths& lengths) const {
    ObservableHistory kept;
    for (const auto& [name, length] : lengths) {
      const auto& samples = history_.at(name);
      kept[name].assign(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(length));
    }
    return granflow::save_history(kept);
  }
  // Writes a saved history again (into `file`, when there is one).
  // With `up_to`, each series' first samples alone (none of a series it lacks).
  void replay(H5mdFile* file, const StateMap& saved, const SeriesLengths* up_to = nullptr) {
    for (const auto& [name, samples] : load_history(saved)) {
      std::size_t count = samples.size();
      if (up_to) {
        const auto length = up_to->find(name);
        count = length == up_to->end() ? 0 : std::min(count, length->second);
      }
      for (std::size_t k = 0; k < count; ++k) append(file, name, samples[k]);
    }
  }

 private:
  std::vector<std::string> observables_;
  ObservableHistory history_;
};

inline StateMap save_history(const ObservableHistory& history) {
  StateMap out;
  for (const auto& [name, samples] : history) {
    auto& step = out[name + "/step"];
    auto& time = out[name + "/time"];
    auto& value = out[name + "/value"];
    auto& width = out[name + "/width"];
    for (const auto& s : samples) {
      step.push_back(static_cast<double>(s.step));
      time.push_back(s.time);
      width.push_back(static_cast<double>(s.value.size()));
      value.insert(value.end(), s.value.begin(), s.value.end());
    }
  }
  return out;
}

inline ObservableHistory load_history(const StateMap& saved) {
  ObservableHistory history;
  for (const auto& [entry, steps] : saved) {
    if (entry.size() < 5 || entry.compare(entry.size() - 5, 5, "/step") != 0) continue;
    const std::string name = entry.substr(0, entry.size() - 5);
    const auto time = saved.find(name + "/time"), value = saved.find(name + "/value"), width = saved.find(name + "/width");
    if (time == saved.end() || value == saved.end() || width == saved.end() || time->second.size() != steps.size() ||
        width->second.size() != steps.size())
      throw std::invalid_argument("checkpoint series '" + name + "' is inconsistent");
    std::size_t at = 0;
    auto& samples = history[name];
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const double w = width->second[k];
      if (!(w >= 0) || at + static_cast<std::size_t>(w) > value->second.size())
        throw std::invalid_argument("checkpoint series '" + name + "' is truncated");
      const auto begin = value->second.begin() + static_cast<std::ptrdiff_t>(at);
      samples.push_back({static_cast<std::int64_t>(steps[k]), time->second[k],
                         {begin, begin + static_cast<std::ptrdiff_t>(w)}});
      at += static_cast<std::size_t>(w);
    }
  }
  return history;
}

}  // namespace granflow