#pragma once
// Latest value of each observable of a run, filled by observer systems and
// emptied into the output by the writer. Slots are created before the run
// starts, so observers writing different slots never touch shared structure
// and may run concurrently.

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace granflow {

struct ObservableSlot {
  std::vector<double> value;  // one entry for a scalar observable
  bool fresh = false;
};

class ObservableStore {
 public:
  static constexpr const char* key = "observables";

  void declare(const std::string& name) { slots_[name]; }
  ObservableSlot& slot(const std::string& name) {
    auto it = slots_.find(name);
    if (it == slots_.end()) throw std::logic_error("observable '" + name + "' was not declared");
    return it->second;
  }
  void set(const std::string& name, double value) {
    auto& s = slot(name);
    s.value.assign(1, value);
    s.fresh = true;
  }
  void set(const std::string& name, std::vector<double> value) {
    auto& s = slot(name);
    s.value = std::move(value);
    s.fresh = true;
  }
  // A scalar observable's latest value (0 before it was first set).
  double scalar(const std::string& name) {
    const auto& value = slot(name).value;
    return value.empty() ? 0.0 : value[0];
  }
  bool declared(const std::string& name) const { return slots_.count(name) != 0; }
  std::map<std::string, ObservableSlot>& slots() { return slots_; }
  const std::map<std::string, ObservableSlot>& slots() const { return slots_; }

 private:
  std::map<std::string, ObservableSlot> slots_;
};

}  // namespace granflow
