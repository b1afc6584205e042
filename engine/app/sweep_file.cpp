#include "engine/app/sweep_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "engine/core/toml_reading.hpp"

namespace granflow {

namespace {

std::string node_text(const toml::node& node) {
  if (const auto text = node.value_exact<std::string>()) return *text;
  if (const auto real = node.value_exact<double>()) return fmt::format("{}", *real);  // shortest round trip
  std::ostringstream out;
  node.visit([&](const auto& value) { out << value; });
  return out.str();
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
      throw sweep_file_error(file, fmt::format("[{}] '{}' must be a non-empty array of values", section, key));
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
  const auto axes = value_lists(*grid, "grid", file);
  double product = 1.0;
  for (const auto& [key, values] : axes) product *= static_cast<double>(values.size());
  if (product > static_cast<double>(max_sweep_points))
    throw sweep_file_error(file, fmt::format("[grid] spans {:.3g} parameter points; at most {} are allowed", product,
                                             max_sweep_points));
  for (const auto& [key, values] : axes) {
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
      throw sweep_file_error(file, fmt::format("[zip] lists must have equal lengths: '{}' has {}, '{}' has {}",
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
    if (!table) throw sweep_file_error(file, "[[points]] entries must be tables of key = value");
    const auto leaves = leaves_in_file_order(*table);
    Assignment point;
    for (const auto& [key, node] : leaves) point.emplace_back(key, node_text(*node));
    points.push_back(std::move(point));
  }
  if (points.empty()) throw sweep_file_error(file, "[[points]] is empty");
  return points;
}

}  // namespace

SweepFile parse_sweep_text(const std::string& text, const std::string& name) {
  const std::string what = "sweep file " + name;
  const toml::table table = parse_toml_text(text, name, what);
  const std::set<std::string> known{"scenario_file", "output", "repeats", "summary", "cost",
                                    "set",           "grid",   "zip",     "points"};
  for (const auto& [key, node] : table)
    if (!known.contains(std::string(key.str())))
      throw sweep_file_error(name, fmt::format("unknown key '{}'; allowed: scenario_file, output, repeats, summary, "
                                               "cost, set, grid, zip, points",
                                               key.str()));
  SweepFile file;
  const auto scenario_file = table["scenario_file"].value_exact<std::string>();
  if (!scenario_file) throw sweep_file_error(name, "needs scenario_file = \"<scenario>.toml\"");
  file.scenario_file = *scenario_file;
  if (table.contains("output")) {
    file.output = table["output"].value_exact<std::string>();
    if (!file.output || file.output->empty())
      throw sweep_file_error(name, "output must be a directory name (a string)");
  }
  if (table.contains("repeats")) {
    const auto repeats = table["repeats"].value_exact<std::int64_t>();
    if (!repeats) throw sweep_file_error(name, "repeats must be an integer");
    if (*repeats < 1 || *repeats > 100000)
      throw sweep_file_error(name, fmt::format("repeats = {} is out of range: allowed is an integer in [1, 100000]",
                                               *repeats));
    file.repeats = static_cast<std::size_t>(*repeats);
  }
  // An array of strings, or the error that says what `key` must be.
  const auto names = [&](const char* key, const char* what_it_is, std::vector<std::string>& out) {
    if (!table.contains(key)) return;
    const auto* array = table[key].as_array();
    const std::string must = fmt::format("{} must be an array of {}", key, what_it_is);
    if (!array) throw sweep_file_error(name, must);
    for (const auto& entry : *array) {
      const auto text_value = entry.value_exact<std::string>();
      if (!text_value) throw sweep_file_error(name, must);
      out.push_back(*text_value);
    }
  };
  names("summary", "observable names", file.summary);
  names("cost", "configuration keys (a run's expected cost grows as the product of their values)", file.cost);
  if (table.contains("set")) {
    const auto* fixed = table["set"].as_table();
    if (!fixed) throw sweep_file_error(name, "[set] must be a table of key = value");
    for (const auto& [key, node] : leaves_in_file_order(*fixed)) file.fixed.emplace_back(key, node_text(*node));
  }
  for (const char* section : {"grid", "zip"})
    if (table.contains(section) && !table[section].as_table())
      throw sweep_file_error(name, fmt::format("[{}] must be a table of key = [values]", section));
  if (table.contains("points") && !table["points"].as_array())
    throw sweep_file_error(name, "[[points]] must be an array of tables");

  // A key swept in two sections would silently lose one of its values.
  std::map<std::string, std::string> section_of;
  const auto claim = [&](const std::string& key, const std::string& section) {
    const auto [it, fresh] = section_of.emplace(key, section);
    if (!fresh && it->second != section)
      throw sweep_file_error(name, fmt::format("'{}' is swept in both [{}] and [{}]; give it in one of them", key,
                                               it->second, section));
  };
  for (const char* section : {"grid", "zip"})
    if (const auto* t = table[section].as_table())
      for (const auto& [key, value] : leaves_in_file_order(*t)) claim(key, section);
  if (const auto* list = table["points"].as_array())
    for (const auto& entry : *list)
      if (const auto* t = entry.as_table())
        for (const auto& [key, value] : leaves_in_file_order(*t)) claim(key, "[points]");

  // Parameter points: grid x zip x listed points.
  std::vector<Assignment> points{{}};
  for (const auto& factor : {grid_points(table["grid"].as_table(), name), zip_points(table["zip"].as_table(), name),
                             listed_points(table["points"].as_array(), name)}) {
    if (static_cast<double>(points.size()) * static_cast<double>(factor.size()) > static_cast<double>(max_sweep_points))
      throw sweep_file_error(name, fmt::format("the sweep spans more than {} parameter points", max_sweep_points));
    std::vector<Assignment> next;
    for (const auto& left : points)
      for (const auto& right : factor) {
        next.push_back(left);
        next.back().insert(next.back().end(), right.begin(), right.end());
      }
    points = std::move(next);
  }
  file.points = std::move(points);
  return file;
}

SweepFile read_sweep_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("cannot read sweep file {}", path));
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_sweep_text(buffer.str(), path);
}

ConfigError sweep_file_error(const std::string& file, const std::string& what) {
  return ConfigError(fmt::format("sweep file {}: {}", file, what));
}

}  // namespace granflow
