#pragma once
// The saved state of anything that continues a run: named flat arrays of
// doubles. Every value a checkpoint holds (integers up to 2^53, indices,
// counters) is exact in a double, so one array type serves all, and a
// checkpoint file is a list of such arrays.

#include <map>
#include <string>
#include <vector>

namespace granflow {

using StateMap = std::map<std::string, std::vector<double>>;

// An object that a checkpoint saves and a resumed run restores: the
// event-driven gas, a correlator, an observer's reference data.
class Stateful {
 public:
  virtual ~Stateful() = default;
  virtual StateMap save_state() const = 0;
  virtual void restore_state(const StateMap& state) = 0;
};

// The entries of `state` under "prefix/", with the prefix removed.
inline StateMap state_under(const StateMap& state, const std::string& prefix) {
  StateMap out;
  const std::string head = prefix + "/";
  for (auto it = state.lower_bound(head); it != state.end() && it->first.compare(0, head.size(), head) == 0; ++it)
    out.emplace(it->first.substr(head.size()), it->second);
  return out;
}

inline void put_state_under(StateMap& state, const std::string& prefix, const StateMap& part) {
  for (const auto& [name, values] : part) state[prefix + "/" + name] = values;
}

}  // namespace granflow
