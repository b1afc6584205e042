#pragma once
// Reading TOML for configurations and sweep files: parse errors become
// ConfigErrors that name the file, line and column, and nested tables are
// flattened into dotted keys ("collision.restitution"), so a key can be
// written as a table entry or as a quoted dotted name alike.

#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "engine/config.hpp"

namespace granflow {

inline ConfigError toml_parse_failure(const std::string& what, const toml::parse_error& error) {
  std::ostringstream text;
  text << error.description() << " (" << error.source() << ")";
  return ConfigError(fmt::format("cannot parse {}: {}", what, text.str()));
}

// `what` names the file in messages, e.g. "sweep file x.toml".
inline toml::table parse_toml_file(const std::string& path, const std::string& what) {
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& error) {
    throw toml_parse_failure(what, error);
  }
}

inline void collect_toml_leaves(const toml::table& table, const std::string& prefix,
                                std::vector<std::pair<std::string, const toml::node*>>& leaves) {
  for (const auto& [name, node] : table) {
    const std::string key = prefix.empty() ? std::string(name.str()) : prefix + "." + std::string(name.str());
    if (const auto* sub = node.as_table())
      collect_toml_leaves(*sub, key, leaves);
    else
      leaves.emplace_back(key, &node);
  }
}

}  // namespace granflow
