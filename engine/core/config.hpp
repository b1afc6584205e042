#pragma once
// Typed, validated configuration. A scenario declares every key it accepts
// (type, default, allowed range or choices, meaning); a TOML file and
// `--set section.key=value` overrides are checked against that schema, so a
// misspelt key or an impossible value stops the run before it starts.

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "engine/core/input_error.hpp"

namespace granflow {

class ConfigError : public InputError {
 public:
  using InputError::InputError;
};

struct ConfigTable;
// A key's value: a scalar, a list of numbers, or a list of tables (walls,
// species, ...) whose keys an element schema declares.
using ConfigValue =
    std::variant<std::int64_t, double, bool, std::string, std::vector<double>, std::vector<ConfigTable>>;
struct ConfigTable {
  std::map<std::string, ConfigValue> values;
  bool operator==(const ConfigTable&) const = default;
};

enum class ValueType { integer, real, boolean, string, real_array, table_array };

class ConfigSchema;

struct KeySpec {
  std::string key;
  ValueType type = ValueType::real;
  ConfigValue default_value;
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  std::vector<std::string> choices;
  std::string help;
  bool allow_infinite = false;  // +inf accepted, meaning "no limit"
  std::string unit;             // of a number, in H5MD notation (engine/core/units.hpp); "1" for pure numbers
  // A resumed run may use another value (a stop criterion, an output
  // setting); every other key must match the checkpoint's.
  bool resume_may_change = false;
  bool resume_fixed = false;  // an output.* key that --resume may not change (it shaped what was already averaged)
  // Lists: how many items; for real_array every item lies in [min, max].
  std::size_t min_items = 0;
  std::size_t max_items = std::numeric_limits<std::size_t>::max();
  std::shared_ptr<const ConfigSchema> element;  // table_array: the keys of each table

  std::string allowed() const;  // human-readable range or choice list
};

class ConfigSchema {
 public:
  ConfigSchema& integer(const std::string& key, std::int64_t def, std::int64_t min, std::int64_t max,
                        const std::string& help);
  // Real in [min, max], or (min, max] when min_exclusive.
  ConfigSchema& real(const std::string& key, double def, double min, double max, const std::string& help,
                     bool min_exclusive = false);
  // Real in [min, inf], where inf means "no limit" (a stop criterion that never triggers).
  ConfigSchema& real_or_infinite(const std::string& key, double def, double min, const std::string& help,
                                 bool min_exclusive = false);
  ConfigSchema& boolean(const std::string& key, bool def, const std::string& help);
  ConfigSchema& choice(const std::string& key, const std::string& def, std::vector<std::string> choices,
                       const std::string& help);
  ConfigSchema& text(const std::string& key, const std::string& def, const std::string& help);
  // A list of numbers, each in [min, max].
  ConfigSchema& real_array(const std::string& key, std::vector<double> def, double min, double max,
                           std::size_t min_items, std::size_t max_items, const std::string& help);
  // A list of tables ([[key]] in TOML), each checked against `element`; empty by default.
  ConfigSchema& table_array(const std::string& key, ConfigSchema element, std::size_t min_items,
                            std::size_t max_items, const std::string& help);

  // Keys under output.* may always change on resume.
  ConfigSchema& allow_change_on_resume(const std::string& key);
  // An output.* key that --resume must keep (output keys may change otherwise).
  ConfigSchema& fixed_on_resume(const std::string& key);
  // The unit of a numeric key (engine/core/units.hpp), shown by `granflow keys`.
  ConfigSchema& unit(const std::string& key, const std::string& unit);

  const KeySpec* find(const std::string& key) const;
  const std::vector<KeySpec>& keys() const { return keys_; }

 private:
  ConfigSchema& add(KeySpec spec);
  // The declared key, for a setter named `who` (a logic error if undeclared).
  KeySpec& declared(const std::string& key, const char* who);
  std::vector<KeySpec> keys_;
};

class Config {
 public:
  Config() = default;
  // All keys at their defaults.
  explicit Config(const ConfigSchema& schema);

  static Config from_toml_text(const ConfigSchema& schema, const std::string& text, const std::string& origin);
  static Config from_file(const ConfigSchema& schema, const std::string& path);

  // "section.key=value"; the value is parsed as the key's declared type.
  void apply_override(const std::string& assignment);
  void set(const std::string& key, const ConfigValue& value);

  std::int64_t integer(const std::string& key) const;
  double real(const std::string& key) const;
  bool boolean(const std::string& key) const;
  const std::string& text(const std::string& key) const;
  const std::vector<double>& reals(const std::string& key) const;
  // Each table as a configuration of the element schema, its defaults filled in.
  std::vector<Config> tables(const std::string& key) const;

  const std::map<std::string, ConfigValue>& values() const { return values_; }
  const ConfigSchema& schema() const { return *schema_; }
  std::string to_toml() const;
  // Keys whose values differ from `other`'s and may not change on resume.
  std::vector<std::string> resume_conflicts(const Config& other) const;

 private:
  const KeySpec& spec(const std::string& key) const;
  const ConfigValue& get(const std::string& key) const;
  void check(const KeySpec& spec, const ConfigValue& value) const;

  const ConfigSchema* schema_ = nullptr;
  std::map<std::string, ConfigValue> values_;
};

// Reads only the top-level `scenario` key of a configuration file.
std::string scenario_name_of(const std::string& path);

std::string to_string(const ConfigValue& value);

}  // namespace granflow
