#pragma once
// Appends every fresh observable to /observables/<name>/{step,time,value}.
// The only system that touches the output file, so HDF5 is never called from
// two threads.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "components/clock.hpp"
#include "engine/h5md_file.hpp"
#include "engine/observable_store.hpp"
#include "engine/system.hpp"
#include "engine/world.hpp"

namespace granflow {

inline constexpr const char* output_file_key = "output_file";

class ObservableWriter : public System {
 public:
  ObservableWriter(H5mdFile& file, std::vector<std::string> observables)
      : file_(file), observables_(std::move(observables)) {}

  std::string name() const override { return "write_observables"; }
  Access access() const override {
    Access access{{Clock::key}, {output_file_key}};
    for (const auto& name : observables_) access.reads.push_back(ObservableStore::access_key(name));
    return access;
  }
  void run(World& world) override {
    const auto& clock = world.resource<Clock>();
    auto& store = world.resource<ObservableStore>();
    for (const auto& name : observables_) {
      auto& slot = store.slot(name);
      if (!slot.fresh) continue;
      append(name, {clock.step, clock.time, slot.value});
      slot.fresh = false;
    }
  }

  struct Sample {
    std::int64_t step;
    double time;
    std::vector<double> value;
  };
  // Everything written so far, so a checkpoint can carry it and a resumed
  // run can write it again into its fresh output file.
  const std::map<std::string, std::vector<Sample>>& history() const { return history_; }
  void append(const std::string& name, const Sample& sample) {
    if (sample.value.size() == 1)
      file_.append_observable(name, sample.step, sample.time, sample.value.front());
    else
      file_.append_observable(name, sample.step, sample.time, sample.value);
    history_[name].push_back(sample);
  }

 private:
  H5mdFile& file_;
  std::vector<std::string> observables_;
  std::map<std::string, std::vector<Sample>> history_;
};

}  // namespace granflow
