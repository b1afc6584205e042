#pragma once
// run.runs: independent runs of an ensemble scenario, member r seeded with
// member_seed(run.seed, r) (engine/run/runner.hpp), the same seeds as a sweep's
// repeats. Statistics over them are taken by the scenario's reduce.

#include <cstdint>

#include "engine/core/config.hpp"

namespace granflow {

inline void declare_ensemble_keys(ConfigSchema& schema, std::int64_t runs) {
  schema.integer("run.runs", runs, 1, 100000, "independent runs (the standard error is taken over them)");
}
inline std::size_t ensemble_members(const Config& config) {
  return static_cast<std::size_t>(config.integer("run.runs"));
}

// The k-th sample of observable `name` of every member, in member order.
template <class Results>
std::vector<double> member_values(const Results& results, const std::string& name, std::size_t k,
                                  std::size_t component = 0) {
  std::vector<double> out;
  for (const auto& member : results.members) out.push_back(member.history.at(name).at(k).value.at(component));
  return out;
}

}  // namespace granflow
