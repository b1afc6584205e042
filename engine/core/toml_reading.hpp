#pragma once
// Reading TOML for configurations and sweep files: parse errors become
// ConfigErrors that name the file, line and column, and nested tables are
// flattened into dotted keys ("collision.restitution"), so a key can be
// written as a table entry or as a quoted dotted name alike.

#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "engine/core/config.hpp"

namespace granflow {

inline ConfigError toml_parse_failure(const std::string& what, const toml::parse_error& error) {
  std::ostringstream text;
  text << error.description() << " (" << error.source() << ")";
  return ConfigError(fmt::format("cannot parse {}: {}", what, text.str()));
}

// toml++ 3.3 reaches code it marks unreachable (undefined behaviour) for
// bare keys with some non-ASCII letters. granflow's keys are ASCII, so any
// byte above 0x7f outside a string or a comment is refused before parsing,
// with its line.
inline void require_ascii_outside_strings(const std::string& text, const std::string& what) {
  std::size_t line = 1;
  char quote = 0;      // inside "..." or '...'
  bool multiline = false;
  bool comment = false;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const char c = text[k];
    if (c == '\n') {
      ++line;
      comment = false;
      if (!multiline) quote = 0;
      continue;
    }
    if (comment) continue;
    if (quote) {
      if (quote == '"' && c == '\\') {
        ++k;  // an escaped character
        continue;
      }
      if (c == quote && (!multiline || text.compare(k, 3, std::string(3, quote)) == 0)) {
        if (multiline) k += 2;
        quote = 0;
        multiline = false;
      }
      continue;
    }
    if (c == '#') {
      comment = true;
    } else if (c == '"' || c == '\'') {
      quote = c;
      multiline = text.compare(k, 3, std::string(3, c)) == 0;
      if (multiline) k += 2;
    } else if (static_cast<unsigned char>(c) > 0x7f) {
      throw ConfigError(fmt::format("cannot parse {}: line {} has a non-ASCII character outside a string or comment "
                                    "(keys are ASCII)",
                                    what, line));
    }
  }
}

// `what` names the text in messages, e.g. "sweep file x.toml"; `source` is
// the path toml++ puts into its positions.
inline toml::table parse_toml_text(const std::string& text, const std::string& source, const std::string& what) {
  require_ascii_outside_strings(text, what);
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& error) {
    throw toml_parse_failure(what, error);
  }
}

inline toml::table parse_toml_file(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("cannot read {}", what));
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_toml_text(buffer.str(), path, what);
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
