#include "engine/core/config.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <toml++/toml.h>

#include "engine/core/suggestion.hpp"
#include "engine/core/toml_reading.hpp"

namespace granflow {

namespace {

const char* type_name(ValueType type) {
  switch (type) {
    case ValueType::integer: return "an integer";
    case ValueType::real: return "a number";
    case ValueType::boolean: return "true or false";
    case ValueType::string: return "a string";
    case ValueType::real_array: return "a list of numbers";
    case ValueType::table_array: return "a list of tables";
  }
  return "?";
}

std::string format_real(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return fmt::format("{}", value);
}

std::string join(const std::vector<std::string>& items, const std::string& separator) {
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k) out += (k ? separator : "") + items[k];
  return out;
}

// Converts a TOML leaf to the declared type, or explains why it cannot.
ConfigValue from_toml_node(const KeySpec& spec, const toml::node& node) {
  switch (spec.type) {
    case ValueType::integer:
      if (auto v = node.value_exact<std::int64_t>()) return *v;
      break;
    case ValueType::real:
      if (auto v = node.value_exact<double>()) return *v;
      if (auto v = node.value_exact<std::int64_t>()) return static_cast<double>(*v);
      break;
    case ValueType::boolean:
      if (auto v = node.value_exact<bool>()) return *v;
      break;
    case ValueType::string:
      if (auto v = node.value_exact<std::string>()) return *v;
      break;
    case ValueType::real_array:
      if (const auto* array = node.as_array()) {
        std::vector<double> values;
        bool numbers = true;
        for (const auto& item : *array) {
          if (auto d = item.value_exact<double>())
            values.push_back(*d);
          else if (auto i = item.value_exact<std::int64_t>())
            values.push_back(static_cast<double>(*i));
          else
            numbers = false;
        }
        if (numbers) return values;
      }
      break;
    case ValueType::table_array:
      if (const auto* array = node.as_array()) {
        std::vector<ConfigTable> tables;
        std::size_t index = 0;
        for (const auto& item : *array) {
          const auto* table = item.as_table();
          if (!table) throw ConfigError(fmt::format("configuration key '{}' must be a list of tables", spec.key));
          const std::string where = fmt::format("{}[{}]", spec.key, index++);
          std::vector<std::pair<std::string, const toml::node*>> leaves;
          collect_toml_leaves(*table, "", leaves);
          Config element(*spec.element);
          for (const auto& [key, leaf] : leaves) {
            const KeySpec* inner = spec.element->find(key);
            if (!inner) {
              std::vector<std::string> known;
              for (const auto& k : spec.element->keys()) known.push_back(k.key);
              throw ConfigError(fmt::format("unknown key '{}' in {}{}", key, where, suggestion_text(key, known, "keys")));
            }
            try {
              element.set(key, from_toml_node(*inner, *leaf));
            } catch (const ConfigError& error) {
              throw ConfigError(fmt::format("{}: {}", where, error.what()));
            }
          }
          tables.push_back({element.values()});
        }
        return tables;
      }
      break;
  }
  std::ostringstream shown;
  node.visit([&](const auto& value) { shown << value; });
  throw ConfigError(fmt::format("configuration key '{}' must be {}, got {}", spec.key, type_name(spec.type),
                                shown.str()));
}

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

// A --set value as TOML: "[46, 46, 46]", "[{x = 0.5}]".
ConfigValue from_toml_text(const KeySpec& spec, const std::string& text) {
  toml::table parsed;
  require_ascii_outside_strings(text, "--set " + spec.key);
  try {
    parsed = toml::parse("value = " + text, "--set " + spec.key);
  } catch (const toml::parse_error& error) {
    throw toml_parse_failure("--set " + spec.key + "=" + text, error);
  }
  return from_toml_node(spec, *parsed.get("value"));
}

ConfigValue from_text(const KeySpec& spec, std::string text) {
  if (spec.type == ValueType::real_array || spec.type == ValueType::table_array) return from_toml_text(spec, text);
  const auto fail = [&] {
    return ConfigError(
        fmt::format("configuration key '{}' must be {}, got '{}'", spec.key, type_name(spec.type), text));
  };
  switch (spec.type) {
    case ValueType::integer: {
      std::int64_t value = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (ec == std::errc() && end == text.data() + text.size() && !text.empty()) return value;
      // 1e6 and 2.5e3 name integers too.
      double real = 0;
      const auto [real_end, real_ec] = std::from_chars(text.data(), text.data() + text.size(), real);
      if (real_ec != std::errc() || real_end != text.data() + text.size() || text.empty() || real != std::floor(real) ||
          std::abs(real) > 9.007199254740992e15)
        throw fail();
      return static_cast<std::int64_t>(real);
    }
    case ValueType::real: {
      double value = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (ec != std::errc() || end != text.data() + text.size() || text.empty()) throw fail();
      return value;
    }
    case ValueType::boolean:
      if (text == "true") return true;
      if (text == "false") return false;
      throw fail();
    case ValueType::string:
      if (text.size() >= 2 && (text.front() == '"' || text.front() == '\'') && text.back() == text.front())
        text = text.substr(1, text.size() - 2);
      return text;
    default: break;
  }
  throw fail();
}

}  // namespace

std::string items_text(std::size_t min_items, std::size_t max_items) {
  if (max_items == std::numeric_limits<std::size_t>::max()) return fmt::format("{} or more", min_items);
  if (min_items == max_items) return std::to_string(min_items);
  return fmt::format("{} to {}", min_items, max_items);
}

std::string KeySpec::allowed() const {
  if (!choices.empty()) return "one of: " + join(choices, ", ");
  switch (type) {
    case ValueType::boolean: return "true or false";
    case ValueType::string: return "a string";
    case ValueType::real_array:
      return fmt::format("a list of {} numbers in [{}, {}]", items_text(min_items, max_items), format_real(min),
                         format_real(max));
    case ValueType::table_array: {
      std::vector<std::string> keys;
      for (const auto& k : element->keys()) keys.push_back(k.key);
      return fmt::format("a list of {} tables with keys {}", items_text(min_items, max_items), join(keys, ", "));
    }
    default: break;
  }
  const auto bound = [&](double v) {
    if (type == ValueType::integer && std::abs(v) >= 9.2e18) return std::string(v > 0 ? "2^63-1" : "-2^63");
    return format_real(v);
  };
  const bool open_above = std::isinf(max) && !allow_infinite;
  return fmt::format("{} in {}{}, {}{}{}", type == ValueType::integer ? "an integer" : "a number",
                     min_exclusive ? "(" : "[", bound(min), bound(max), open_above ? ")" : "]",
                     allow_infinite ? " (inf: no limit)" : "");
}

ConfigSchema& ConfigSchema::add(KeySpec spec) {
  if (find(spec.key)) throw std::logic_error("configuration key declared twice: " + spec.key);
  keys_.push_back(std::move(spec));
  return *this;
}

ConfigSchema& ConfigSchema::integer(const std::string& key, std::int64_t def, std::int64_t min, std::int64_t max,
                                    const std::string& help) {
  return add({key, ValueType::integer, def, static_cast<double>(min), static_cast<double>(max), false, {}, help});
}

ConfigSchema& ConfigSchema::real(const std::string& key, double def, double min, double max, const std::string& help,
                                 bool min_exclusive) {
  return add({key, ValueType::real, def, min, max, min_exclusive, {}, help});
}

ConfigSchema& ConfigSchema::real_or_infinite(const std::string& key, double def, double min,
                                             const std::string& help, bool min_exclusive) {
  KeySpec spec{key, ValueType::real, def, min, std::numeric_limits<double>::infinity(), min_exclusive, {}, help};
  spec.allow_infinite = true;
  return add(std::move(spec));
}

ConfigSchema& ConfigSchema::boolean(const std::string& key, bool def, const std::string& help) {
  return add({key, ValueType::boolean, def, 0, 0, false, {}, help});
}

ConfigSchema& ConfigSchema::choice(const std::string& key, const std::string& def, std::vector<std::string> choices,
                                   const std::string& help) {
  return add({key, ValueType::string, def, 0, 0, false, std::move(choices), help});
}

ConfigSchema& ConfigSchema::text(const std::string& key, const std::string& def, const std::string& help) {
  return add({key, ValueType::string, def, 0, 0, false, {}, help});
}

ConfigSchema& ConfigSchema::unit(const std::string& key, const std::string& unit) {
  declared(key, "unit").unit = unit;
  return *this;
}

KeySpec& ConfigSchema::declared(const std::string& key, const char* who) {
  for (auto& spec : keys_)
    if (spec.key == key) return spec;
  throw std::logic_error(std::string(who) + ": no key " + key);
}

ConfigSchema& ConfigSchema::allow_change_on_resume(const std::string& key) {
  declared(key, "allow_change_on_resume").resume_may_change = true;
  return *this;
}

ConfigSchema& ConfigSchema::fixed_on_resume(const std::string& key) {
  declared(key, "fixed_on_resume").resume_fixed = true;
  return *this;
}

ConfigSchema& ConfigSchema::real_array(const std::string& key, std::vector<double> def, double min, double max,
                                       std::size_t min_items, std::size_t max_items, const std::string& help) {
  KeySpec spec{key, ValueType::real_array, std::move(def), min, max, false, {}, help};
  spec.min_items = min_items;
  spec.max_items = max_items;
  return add(std::move(spec));
}

ConfigSchema& ConfigSchema::table_array(const std::string& key, ConfigSchema element, std::size_t min_items,
                                        std::size_t max_items, const std::string& help) {
  KeySpec spec{key, ValueType::table_array, std::vector<ConfigTable>{}, 0, 0, false, {}, help};
  spec.min_items = min_items;
  spec.max_items = max_items;
  spec.element = std::make_shared<const ConfigSchema>(std::move(element));
  return add(std::move(spec));
}

const KeySpec* ConfigSchema::find(const std::string& key) const {
  for (const auto& spec : keys_)
    if (spec.key == key) return &spec;
  return nullptr;
}

Config::Config(const ConfigSchema& schema) : schema_(&schema) {
  for (const auto& spec : schema.keys()) values_[spec.key] = spec.default_value;
}

Config Config::from_toml_text(const ConfigSchema& schema, const std::string& text, const std::string& origin) {
  Config config(schema);
  const toml::table table = parse_toml_text(text, origin, origin);
  std::vector<std::pair<std::string, const toml::node*>> leaves;
  collect_toml_leaves(table, "", leaves);
  for (const auto& [key, node] : leaves) {
    const KeySpec* spec = schema.find(key);
    if (!spec) {
      std::vector<std::string> known;
      for (const auto& s : schema.keys()) known.push_back(s.key);
      throw ConfigError(fmt::format("unknown configuration key '{}' in {}{} (`granflow keys` lists them with their "
                                    "ranges)",
                                    key, origin, suggestion_text(key, known, "keys")));
    }
    config.set(key, from_toml_node(*spec, *node));
  }
  return config;
}

Config Config::from_file(const ConfigSchema& schema, const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(fmt::format("cannot open configuration file '{}'", path));
  std::stringstream buffer;
  buffer << in.rdbuf();
  return from_toml_text(schema, buffer.str(), path);
}

void Config::apply_override(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ConfigError(fmt::format("--set expects section.key=value, got '{}'", assignment));
  const std::string key = trimmed(assignment.substr(0, eq));
  set(key, from_text(spec(key), trimmed(assignment.substr(eq + 1))));
}

void Config::set(const std::string& key, const ConfigValue& value) {
  const KeySpec& s = spec(key);
  ConfigValue converted = value;
  if (s.type == ValueType::real && std::holds_alternative<std::int64_t>(value))
    converted = static_cast<double>(std::get<std::int64_t>(value));
  check(s, converted);
  values_[key] = converted;
}

const KeySpec& Config::spec(const std::string& key) const {
  if (!schema_) throw std::logic_error("configuration has no schema");
  const KeySpec* s = schema_->find(key);
  if (!s) {
    std::vector<std::string> known;
    for (const auto& k : schema_->keys()) known.push_back(k.key);
    throw ConfigError(fmt::format("unknown configuration key '{}'{} (`granflow keys` lists them with their ranges)",
                                  key, suggestion_text(key, known, "keys")));
  }
  return *s;
}

void Config::check(const KeySpec& s, const ConfigValue& value) const {
  const auto out_of_range = [&](const std::string& shown) {
    return ConfigError(fmt::format("configuration key '{}' = {} is out of range: allowed is {}", s.key, shown,
                                   s.allowed()));
  };
  switch (s.type) {
    case ValueType::integer: {
      if (!std::holds_alternative<std::int64_t>(value))
        throw ConfigError(fmt::format("configuration key '{}' must be an integer", s.key));
      const auto v = static_cast<double>(std::get<std::int64_t>(value));
      if (v < s.min || v > s.max) throw out_of_range(std::to_string(std::get<std::int64_t>(value)));
      break;
    }
    case ValueType::real: {
      if (!std::holds_alternative<double>(value))
        throw ConfigError(fmt::format("configuration key '{}' must be a number", s.key));
      const double v = std::get<double>(value);
      if (!std::isfinite(v) && !(s.allow_infinite && v > 0)) throw out_of_range(format_real(v));
      if (v > s.max || v < s.min || (s.min_exclusive && v == s.min)) throw out_of_range(format_real(v));
      break;
    }
    case ValueType::boolean:
      if (!std::holds_alternative<bool>(value))
        throw ConfigError(fmt::format("configuration key '{}' must be true or false", s.key));
      break;
    case ValueType::real_array: {
      if (!std::holds_alternative<std::vector<double>>(value))
        throw ConfigError(fmt::format("configuration key '{}' must be a list of numbers", s.key));
      const auto& items = std::get<std::vector<double>>(value);
      if (items.size() < s.min_items || items.size() > s.max_items)
        throw ConfigError(fmt::format("configuration key '{}' has {} items: allowed is {}", s.key, items.size(),
                                      s.allowed()));
      for (double v : items)
        if (!std::isfinite(v) || v < s.min || v > s.max)
          throw ConfigError(fmt::format("configuration key '{}' holds {}, out of range: allowed is {}", s.key,
                                        format_real(v), s.allowed()));
      break;
    }
    case ValueType::table_array: {
      if (!std::holds_alternative<std::vector<ConfigTable>>(value))
        throw ConfigError(fmt::format("configuration key '{}' must be a list of tables", s.key));
      const auto& items = std::get<std::vector<ConfigTable>>(value);
      if (items.size() < s.min_items || items.size() > s.max_items)
        throw ConfigError(fmt::format("configuration key '{}' has {} tables: allowed is {}", s.key, items.size(),
                                      s.allowed()));
      break;
    }
    case ValueType::string: {
      if (!std::holds_alternative<std::string>(value))
        throw ConfigError(fmt::format("configuration key '{}' must be a string", s.key));
      const auto& v = std::get<std::string>(value);
      if (!s.choices.empty() && std::find(s.choices.begin(), s.choices.end(), v) == s.choices.end())
        throw ConfigError(fmt::format("configuration key '{}' = '{}' is not allowed: use {}", s.key, v,
                                      s.allowed()));
      break;
    }
  }
}

const ConfigValue& Config::get(const std::string& key) const {
  spec(key);
  return values_.at(key);
}

std::int64_t Config::integer(const std::string& key) const { return std::get<std::int64_t>(get(key)); }
double Config::real(const std::string& key) const { return std::get<double>(get(key)); }
bool Config::boolean(const std::string& key) const { return std::get<bool>(get(key)); }
const std::string& Config::text(const std::string& key) const { return std::get<std::string>(get(key)); }
const std::vector<double>& Config::reals(const std::string& key) const {
  return std::get<std::vector<double>>(get(key));
}
std::vector<Config> Config::tables(const std::string& key) const {
  const KeySpec& s = spec(key);
  std::vector<Config> out;
  for (const auto& table : std::get<std::vector<ConfigTable>>(get(key))) {
    Config element(*s.element);
    for (const auto& [name, value] : table.values) element.set(name, value);
    out.push_back(std::move(element));
  }
  return out;
}

std::string to_string(const ConfigValue& value) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::string>) {
          std::ostringstream out;
          out << toml::value<std::string>(v);
          return out.str();
        } else if constexpr (std::is_same_v<T, bool>) {
          return v ? "true" : "false";
        } else if constexpr (std::is_same_v<T, double>) {
          if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
          std::string shown = fmt::format("{}", v);
          if (shown.find_first_of(".eEn") == std::string::npos) shown += ".0";
          return shown;
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          std::vector<std::string> items;
          for (double x : v) items.push_back(to_string(ConfigValue(x)));
          return fmt::format("[{}]", join(items, ", "));
        } else if constexpr (std::is_same_v<T, std::vector<ConfigTable>>) {
          std::vector<std::string> tables;
          for (const auto& table : v) {
            std::vector<std::string> entries;
            for (const auto& [name, entry] : table.values) entries.push_back(fmt::format("{} = {}", name, to_string(entry)));
            tables.push_back(fmt::format("{{{}}}", join(entries, ", ")));
          }
          return fmt::format("[{}]", join(tables, ", "));
        } else {
          return std::to_string(v);
        }
      },
      value);
}

std::string Config::to_toml() const {
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> sections;
  std::string top;
  for (const auto& [key, value] : values_) {
    const auto dot = key.rfind('.');
    if (dot == std::string::npos)
      top += key + " = " + to_string(value) + "\n";
    else
      sections[key.substr(0, dot)].emplace_back(key.substr(dot + 1), to_string(value));
  }
  std::string out = top;
  for (const auto& [section, entries] : sections) {
    out += "\n[" + section + "]\n";
    for (const auto& [name, value] : entries) out += name + " = " + value + "\n";
  }
  return out;
}

std::vector<std::string> Config::resume_conflicts(const Config& other) const {
  std::vector<std::string> out;
  for (const auto& [key, value] : values_) {
    const KeySpec& s = spec(key);
    if (s.resume_may_change || (key.rfind("output.", 0) == 0 && !s.resume_fixed)) continue;
    const auto it = other.values_.find(key);
    if (it == other.values_.end() || it->second != value) out.push_back(key);
  }
  for (const auto& [key, value] : other.values_)
    if (!values_.count(key)) out.push_back(key);
  return out;
}

std::string scenario_name_of(const std::string& path) {
  if (!std::filesystem::exists(path)) throw ConfigError(fmt::format("configuration file '{}' does not exist", path));
  if (!std::ifstream(path)) throw ConfigError(fmt::format("cannot open configuration file '{}'", path));
  const toml::table table = parse_toml_file(path, path);
  if (!table.contains("scenario"))
    throw ConfigError(fmt::format("configuration file '{}' has no top-level key 'scenario'", path));
  const auto name = table["scenario"].value_exact<std::string>();
  if (!name)
    throw ConfigError(fmt::format("configuration file '{}': 'scenario' must be a scenario name in quotes (see "
                                  "`granflow list`)",
                                  path));
  return *name;
}

}  // namespace granflow
