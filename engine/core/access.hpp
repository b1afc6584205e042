#pragma once
// What a system reads and writes, declared by type: a component column, a
// resource, or one named part of a resource (an observable of the
// ObservableStore). The Schedule derives its graph from these declarations
// alone. A system that may reorder particles (World::permute) declares that
// it writes every component, so nothing that reads any column can run beside it.

#include <string>
#include <type_traits>
#include <utility>
#include <typeindex>
#include <vector>

#include "engine/core/observable_store.hpp"
#include "engine/core/world.hpp"

namespace granflow {

struct AccessKey {
  enum class Kind { component, resource, every_component };
  Kind kind;
  std::type_index type;
  std::string part;  // empty: the whole resource
  std::string label; // for messages and graph dumps

  // True when a write of one may not overlap any use of the other.
  bool overlaps(const AccessKey& other) const {
    if (kind == Kind::every_component || other.kind == Kind::every_component)
      return kind != Kind::resource && other.kind != Kind::resource;
    if (kind != other.kind || type != other.type) return false;
    return part.empty() || other.part.empty() || part == other.part;
  }
};

template <class T>
AccessKey access_key_of(std::string part = {}) {
  constexpr bool is_component = std::is_base_of_v<ColumnBase, T>;
  std::string label = T::key;
  if (!part.empty()) label += ":" + part;
  return {is_component ? AccessKey::Kind::component : AccessKey::Kind::resource, std::type_index(typeid(T)),
          std::move(part), std::move(label)};
}

class Access {
 public:
  template <class... T>
  Access& reads() {
    (reads_.push_back(access_key_of<T>()), ...);
    return *this;
  }
  template <class... T>
  Access& writes() {
    (writes_.push_back(access_key_of<T>()), ...);
    return *this;
  }
  Access& reads_observable(const std::string& name) {
    reads_.push_back(access_key_of<ObservableStore>(name));
    return *this;
  }
  // `unit`: the observable's unit in H5MD notation (engine/core/units.hpp), put
  // into the result file; empty where another system already declared it.
  Access& writes_observable(const std::string& name, const std::string& unit = "") {
    writes_.push_back(access_key_of<ObservableStore>(name));
    if (!unit.empty()) units_.emplace_back(name, unit);
    return *this;
  }
  Access& writes_every_component() {
    writes_.push_back({AccessKey::Kind::every_component, std::type_index(typeid(World)), {}, "every component"});
    return *this;
  }

  const std::vector<AccessKey>& read_keys() const { return reads_; }
  const std::vector<AccessKey>& write_keys() const { return writes_; }
  // Units of the observables this access writes, where it gives them.
  const std::vector<std::pair<std::string, std::string>>& observable_units() const { return units_; }
  // Names of the observables this access writes (the Runner creates their slots).
  std::vector<std::string> written_observables() const {
    std::vector<std::string> out;
    for (const auto& key : writes_)
      if (key.type == std::type_index(typeid(ObservableStore)) && !key.part.empty()) out.push_back(key.part);
    return out;
  }

 private:
  std::vector<AccessKey> reads_;
  std::vector<AccessKey> writes_;
  std::vector<std::pair<std::string, std::string>> units_;
};

// True when two systems may not run at the same time.
inline bool accesses_conflict(const Access& a, const Access& b) {
  const auto writes_touch = [](const Access& writer, const Access& other) {
    for (const auto& w : writer.write_keys()) {
      for (const auto& r : other.read_keys())
        if (w.overlaps(r)) return true;
      for (const auto& o : other.write_keys())
        if (w.overlaps(o)) return true;
    }
    return false;
  };
  return writes_touch(a, b) || writes_touch(b, a);
}

}  // namespace granflow
