#include "engine/app/sweep_plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "engine/app/sweep_file.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/run/runner.hpp"
#include "engine/run/scenario.hpp"

namespace granflow {

namespace {

// The product of the cost keys' values in `config` (an array counts as the
// product of its entries: a box's volume).
double run_cost(const Config& config, const std::vector<std::string>& keys, const std::string& file) {
  double cost = 1.0;
  for (const auto& key : keys) {
    if (!config.schema().find(key))
      throw sweep_file_error(file, fmt::format("cost key '{}' is not a configuration key", key));
    const ConfigValue& value = config.values().at(key);
    if (const auto* integer = std::get_if<std::int64_t>(&value)) cost *= static_cast<double>(*integer);
    else if (const auto* real = std::get_if<double>(&value)) cost *= *real;
    else if (const auto* reals = std::get_if<std::vector<double>>(&value))
      for (double r : *reals) cost *= r;
    else throw sweep_file_error(file, fmt::format("cost key '{}' is not a number or an array of numbers", key));
  }
  if (!(cost > 0.0) || !std::isfinite(cost))
    throw sweep_file_error(file,
                           fmt::format("the cost keys give a run a cost of {}; it must be positive and finite", cost));
  return cost;
}

}  // namespace

std::int64_t repeat_seed(std::int64_t base, std::size_t repeat) {
  return static_cast<std::int64_t>(member_seed(base, repeat));
}

SweepPlan read_sweep_plan(const std::string& sweep_file, const std::string& output_directory) {
  const SweepFile file = read_sweep_file(sweep_file);
  SweepPlan plan;
  plan.scenario_file = std::filesystem::path(sweep_file).parent_path() / file.scenario_file;
  plan.scenario = scenario_name_of(plan.scenario_file.string());
  const Scenario* scenario = scenario_registry().find(plan.scenario);
  if (!scenario) throw sweep_file_error(sweep_file, fmt::format("unknown scenario '{}'", plan.scenario));
  plan.directory = !output_directory.empty() ? std::filesystem::path(output_directory)
                   : file.output                ? std::filesystem::path(*file.output)
                               : std::filesystem::path(std::filesystem::path(sweep_file).stem().string());
  plan.repeats = file.repeats;
  if (file.points.size() * file.repeats > 10 * max_sweep_points)
    throw sweep_file_error(sweep_file, fmt::format("{} parameter points x {} repeats = {} runs; at most {} are allowed",
                                                   file.points.size(), file.repeats, file.points.size() * file.repeats,
                                                   10 * max_sweep_points));
  plan.summary = file.summary;
  plan.cost_keys = file.cost;

  Config base = Config::from_file(scenario_registry().schema(scenario->name), plan.scenario_file.string());
  for (const auto& [key, value] : file.fixed) base.apply_override(key + "=" + value);

  const auto& points = file.points;
  // Every key of every point before any point is planned, so that a
  // misspelling in the last point is named as such.
  for (std::size_t p = 0; p < points.size(); ++p)
    for (const auto& [key, value] : points[p])
      if (!base.schema().find(key))
        throw sweep_file_error(sweep_file, fmt::format("parameter point {}: unknown configuration key '{}'", p, key));
  std::set<std::string> seen;
  for (const auto& point : points)
    for (const auto& [key, value] : point)
      if (seen.insert(key).second) plan.swept_keys.push_back(key);
  const bool seed_swept = seen.contains("run.seed");
  if (plan.repeats > 1 && !base.schema().find("run.seed"))
    throw sweep_file_error(sweep_file,
                           fmt::format("repeats need a run.seed key, which scenario '{}' lacks", plan.scenario));
  if (plan.repeats > 1 && seed_swept)
    throw sweep_file_error(sweep_file, "run.seed is swept explicitly; then repeats must be 1");

  const int digits = std::max<int>(3, static_cast<int>(std::to_string(points.size() - 1).size()));
  for (std::size_t p = 0; p < points.size(); ++p) {
    Config config = base;
    std::vector<std::string> row(plan.swept_keys.size());
    for (const auto& [key, value] : points[p]) {
      try {
        config.apply_override(key + "=" + value);
      } catch (const ConfigError& error) {
        throw sweep_file_error(sweep_file, fmt::format("parameter point {}: {}", p, error.what()));
      }
      row[static_cast<std::size_t>(std::find(plan.swept_keys.begin(), plan.swept_keys.end(), key) -
                                   plan.swept_keys.begin())] = value;
    }
    // Keys a point does not set keep the base value; show it in the table.
    for (std::size_t k = 0; k < row.size(); ++k)
      if (row[k].empty()) row[k] = to_string(config.values().at(plan.swept_keys[k]));
    plan.parameter_values.push_back(row);
    const std::int64_t base_seed = base.schema().find("run.seed") ? config.integer("run.seed") : 0;
    // The seed does not change what a run costs.
    const double cost = run_cost(config, plan.cost_keys, sweep_file);
    for (std::size_t r = 0; r < plan.repeats; ++r)
      plan.runs.push_back(
          {p, r, repeat_seed(base_seed, r), plan.directory / fmt::format("p{:0{}}_r{:02}.h5md", p, digits, r), cost});
    plan.point_configs.push_back(std::move(config));
  }
  return plan;
}

Config SweepPlan::run_config(std::size_t k) const {
  const SweepRun& run = runs.at(k);
  Config config = point_configs.at(run.parameter_point);
  if (repeats > 1) config.set("run.seed", run.seed);
  return config;
}

}  // namespace granflow
