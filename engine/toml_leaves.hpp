#pragma once
// Flattens nested TOML tables into dotted keys ("collision.restitution"), so a
// key can be written as a table entry or as a quoted dotted name alike.

#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

namespace granflow {

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
