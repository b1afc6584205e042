#include "engine/sweep_plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "engine/rng.hpp"
#include "engine/runner.hpp"
#include "engine/scenario.hpp"
#include "engine/stream_ids.hpp"
#include "engine/toml_reading.hpp"

namespace granflow {

namespace {

using Assignment = std::vector<std::pair<std::string, std::string>>;  // key, value as text

std::string node_text(const toml::node& node) {
  if (const auto text = node.value_exact<std::string>()) return *text;
  if (const auto real = node.value_exact<double>()) return fmt::format("{}", *real);  // shortest round trip
  std::ostringstream out;
  node.visit([&](const auto& value) { out << value; });
  return out.str();
}

ConfigError plan_error(const std::string& file, const std::string& what) {
  return ConfigError(fmt::format("sweep file {}: {}", file, what));
}

// Leaves of a table in the order they are written in the file (toml++
// iterates tables sorted by key).
std::vector<std::pair<std::string, const toml::node*>> leaves_in_file_order(const toml::table& table) {
  std::vector<std::pair<std::string, const toml::node*>> leaves;
  collect_toml_leaves(table, "", leaves);
  std::stable_sort(leaves.begin(), leaves.end(), [](const auto& a, const auto& b) {
    const auto& pa = a.second->source().begin;
    const auto& pb = b.second->source().begin;
    return pa.line != pb.line ? pa.line < pb.line : pa.column < pb.column;
  });
  return leaves;
}

// Every key of `table` maps to an array of values.
std::vector<std::pair<std::string, std::vector<std::string>>> value_lists(const toml::table& table,
                                                                        const std::string& section,
                                                                        const std::string& file) {
  const auto leaves = leaves_in_file_order(table);
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  for (const auto& [key, node] : leaves) {
    const auto* array = node->as_array();
    if (!array || array->empty())
      throw plan_error(file, fmt::format("[{}] '{}' must be a non-empty array of values", section, key));
    std::vector<std::string> values;
    for (const auto& element : *array) values.push_back(node_text(element));
    out.emplace_back(key, std::move(values));
  }
  return out;
}

// Cartesian product of the [grid] axes, the first written varying slowest.
std::vector<Assignment> grid_points(const toml::table* grid, const std::string& file) {
  std::vector<Assignment> points{{}};
  if (!grid) return points;
  for (const auto& [key, values] : value_lists(*grid, "grid", file)) {
    std::vector<Assignment> next;
    for (const auto& point : points)
      for (const auto& value : values) {
        next.push_back(point);
        next.back().emplace_back(key, value);
      }
    points = std::move(next);
  }
  return points;
}

// [zip]: every key has a list of the same length; the k-th values go together.
std::vector<Assignment> zip_points(const toml::table* zip, const std::string& file) {
  if (!zip) return {{}};
  const auto lists = value_lists(*zip, "zip", file);
  if (lists.empty()) return {{}};
  const std::size_t length = lists.front().second.size();
  for (const auto& [key, values] : lists)
    if (values.size() != length)
      throw plan_error(file, fmt::format("[zip] lists must have equal lengths: '{}' has {}, '{}' has {}",
                                         lists.front().first, length, key, values.size()));
  std::vector<Assignment> points(length);
  for (std::size_t k = 0; k < length; ++k)
    for (const auto& [key, values] : lists) points[k].emplace_back(key, values[k]);
  return points;
}

// [[points]]: an explicit list of tables of key = value.
std::vector<Assignment> listed_points(const toml::array* list, const std::string& file) {
  if (!list) return {{}};
  std::vector<Assignment> points;
  for (const auto& element : *list) {
    const auto* table = element.as_table();
    if (!table) throw plan_error(file, "[[points]] entries must be tables of key = value");
    const auto leaves = leaves_in_file_order(*table);
    Assignment point;
    for (const auto& [key, node] : leaves) point.emplace_back(key, node_text(*node));
    points.push_back(std::move(point));
  }
  if (points.empty()) throw plan_error(file, "[[points]] is empty");
  return points;
}

}  // namespace

std::int64_t repeat_seed(std::int64_t base, std::size_t repeat) {
  return static_cast<std::int64_t>(member_seed(base, repeat));
}

SweepPlan read_sweep_plan(const std::string& sweep_file, const std::string& output_directory) {
  const toml::table table = parse_toml_file(sweep_file, "sweep file " + sweep_file);
  const std::set<std::string> known{"scenario_file", "output", "repeats", "summary", "set", "grid", "zip", "points"};
  for (const auto& [name, node] : table)
    if (!known.contains(std::string(name.str())))
      throw plan_error(sweep_file, fmt::format("unknown key '{}'; allowed: scenario_file, output, repeats, summary, "
                                               "set, grid, zip, points",
                                               name.str()));

  SweepPlan plan;
  const auto scenario_file = table["scenario_file"].value<std::string>();
  if (!scenario_file) throw plan_error(sweep_file, "needs scenario_file = \"<scenario>.toml\"");
  plan.scenario_file = std::filesystem::path(sweep_file).parent_path() / *scenario_file;
  plan.scenario = scenario_name_of(plan.scenario_file.string());
  const Scenario* scenario = scenario_registry().find(plan.scenario);
  if (!scenario) throw plan_error(sweep_file, fmt::format("unknown scenario '{}'", plan.scenario));

  plan.directory = !output_directory.empty() ? std::filesystem::path(output_directory)
                   : table["output"].value<std::string>()
                       ? std::filesystem::path(*table["output"].value<std::string>())
                       : std::filesystem::path(std::filesystem::path(sweep_file).stem().string());
  const auto repeats = table["repeats"].value_exact<std::int64_t>().value_or(1);
  if (table.contains("repeats") && !table["repeats"].value_exact<std::int64_t>())
    throw plan_error(sweep_file, "repeats must be an integer");
  if (repeats < 1 || repeats > 100000)
    throw plan_error(sweep_file, fmt::format("repeats = {} is out of range: allowed is an integer in [1, 100000]",
                                             repeats));
  plan.repeats = static_cast<std::size_t>(repeats);
  if (const auto* summary = table["summary"].as_array()) {
    for (const auto& name : *summary) {
      const auto text = name.value<std::string>();
      if (!text) throw plan_error(sweep_file, "summary must be an array of observable names");
      plan.summary.push_back(*text);
    }
  } else if (table.contains("summary")) {
    throw plan_error(sweep_file, "summary must be an array of observable names");
  }

  Config base = Config::from_file(scenario_registry().schema(scenario->name), plan.scenario_file.string());
  if (const auto* fixed = table["set"].as_table()) {
    std::vector<std::pair<std::string, const toml::node*>> leaves;
    collect_toml_leaves(*fixed, "", leaves);
    for (const auto& [key, node] : leaves) base.apply_override(key + "=" + node_text(*node));
  }

  // Parameter points: grid x zip x listed points.
  std::vector<Assignment> points{{}};
  for (const auto& factor : {grid_points(table["grid"].as_table(), sweep_file),
                             zip_points(table["zip"].as_table(), sweep_file),
                             listed_points(table["points"].as_array(), sweep_file)}) {
    std::vector<Assignment> next;
    for (const auto& left : points)
      for (const auto& right : factor) {
        next.push_back(left);
        next.back().insert(next.back().end(), right.begin(), right.end());
      }
    points = std::move(next);
  }
  std::set<std::string> seen;
  for (const auto& point : points)
    for (const auto& [key, value] : point)
      if (seen.insert(key).second) plan.swept_keys.push_back(key);
  const bool seed_swept = seen.contains("run.seed");
  if (plan.repeats > 1 && !base.schema().find("run.seed"))
    throw plan_error(sweep_file, fmt::format("repeats need a run.seed key, which scenario '{}' lacks", plan.scenario));
  if (plan.repeats > 1 && seed_swept)
    throw plan_error(sweep_file, "run.seed is swept explicitly; then repeats must be 1");

  const int digits = std::max<int>(3, static_cast<int>(std::to_string(points.size() - 1).size()));
  for (std::size_t p = 0; p < points.size(); ++p) {
    Config config = base;
    std::vector<std::string> row(plan.swept_keys.size());
    for (const auto& [key, value] : points[p]) {
      try {
        config.apply_override(key + "=" + value);
      } catch (const ConfigError& error) {
        throw plan_error(sweep_file, fmt::format("parameter point {}: {}", p, error.what()));
      }
      row[static_cast<std::size_t>(std::find(plan.swept_keys.begin(), plan.swept_keys.end(), key) -
                                   plan.swept_keys.begin())] = value;
    }
    // Keys a point does not set keep the base value; show it in the table.
    for (std::size_t k = 0; k < row.size(); ++k)
      if (row[k].empty()) row[k] = to_string(config.values().at(plan.swept_keys[k]));
    plan.parameter_values.push_back(row);
    const std::int64_t base_seed = base.schema().find("run.seed") ? config.integer("run.seed") : 0;
    for (std::size_t r = 0; r < plan.repeats; ++r) {
      SweepRun run{p, r, repeat_seed(base_seed, r), config, {}};
      if (plan.repeats > 1) run.config.set("run.seed", run.seed);
      run.output = plan.directory / fmt::format("p{:0{}}_r{:02}.h5", p, digits, r);
      plan.runs.push_back(std::move(run));
    }
  }
  return plan;
}

}  // namespace granflow
