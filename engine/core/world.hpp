#pragma once
// The World owns every particle component (one contiguous column per
// component type) and the singleton resources. Systems reach both by type.
//
// Checkpoints save every column without knowing its type (as doubles, with
// the number of values per particle). A resumed run restores that data
// untyped; each column becomes typed again the first time a system asks for
// it, so no scenario has to list its components and no column is dropped:
// one that nobody asks for is carried through permutations and into the next
// checkpoint as it is.

#include <tbb/parallel_for.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <typeindex>
#include <unordered_map>
#include <vector>

#include "engine/core/page_release.hpp"
#include "engine/core/state_map.hpp"

namespace granflow {

// Type-erased view of a component column, so the World can resize, reorder
// and save every column without knowing its type.
class ColumnBase {
 public:
  virtual ~ColumnBase() = default;
  virtual void resize(std::size_t count) = 0;
  virtual void reserve(std::size_t count) = 0;
  // Empties the column and gives its memory back.
  virtual void release() = 0;
  // new_values[k] = old_values[order[k]]
  virtual void permute(const std::vector<std::uint32_t>& order) = 0;
  virtual std::size_t bytes_per_entity() const = 0;
  virtual std::size_t values_per_entity() const = 0;
  virtual std::vector<double> save() const = 0;
  virtual void restore(const std::vector<double>& data) = 0;
};

namespace detail {
template <class T>
constexpr std::size_t values_in() {
  if constexpr (std::is_arithmetic_v<T>)
    return 1;
  else
    return static_cast<std::size_t>(T::RowsAtCompileTime);
}
}  // namespace detail

// A component is a struct deriving from Column<T> with a static `key` naming it.
template <class T>
struct Column : ColumnBase {
  using value_type = T;
  std::vector<T> values;

  T& operator[](std::size_t i) { return values[i]; }
  const T& operator[](std::size_t i) const { return values[i]; }
  std::size_t size() const { return values.size(); }
  T* data() { return values.data(); }
  const T* data() const { return values.data(); }

  void resize(std::size_t count) override { values.resize(count); }
  void reserve(std::size_t count) override { values.reserve(count); }
  void release() override { std::vector<T>().swap(values); }
  void permute(const std::vector<std::uint32_t>& order) override {
    // The room the column had stays: a column that grows again after a
    // reordering (a step over ranks adds its neighbours' particles) then
    // moves nothing.
    std::vector<T> reordered;
    reordered.reserve(values.capacity());
    reordered.resize(order.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 1u << 14), [&](const auto& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) reordered[k] = values[order[k]];
    });
    values.swap(reordered);
  }
  std::size_t bytes_per_entity() const override { return sizeof(T); }
  std::size_t values_per_entity() const override { return detail::values_in<T>(); }
  std::vector<double> save() const override {
    constexpr std::size_t width = detail::values_in<T>();
    std::vector<double> out;
    out.reserve(values.size() * width);
    for (const T& v : values) {
      if constexpr (std::is_arithmetic_v<T>)
        out.push_back(static_cast<double>(v));
      else
        for (std::size_t a = 0; a < width; ++a) out.push_back(static_cast<double>(v[static_cast<int>(a)]));
    }
    return out;
  }
  void restore(const std::vector<double>& data) override {
    constexpr std::size_t width = detail::values_in<T>();
    values.resize(data.size() / width);
    for (std::size_t i = 0; i < values.size(); ++i) {
      if constexpr (std::is_arithmetic_v<T>) {
        values[i] = static_cast<T>(data[i]);
      } else {
        using Scalar = typename T::Scalar;
        for (std::size_t a = 0; a < width; ++a) values[i][static_cast<int>(a)] = static_cast<Scalar>(data[i * width + a]);
      }
    }
  }
};

class World {
 public:
  using PermutationListener = std::function<void(const std::vector<std::uint32_t>& order)>;

  explicit World(std::size_t entity_count = 0) : count_(entity_count) {}
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  World(World&&) = default;
  World& operator=(World&&) = default;

  std::size_t size() const { return count_; }

  void resize(std::size_t entity_count) {
    count_ = entity_count;
    for (auto& [type, entry] : components_) entry.column->resize(count_);
  }
  // No entities, and the columns' memory given back (the columns stay).
  void release() {
    count_ = 0;
    for (auto& [type, entry] : components_) entry.column->release();
  }
  // Room for `entity_count` entities in every column, so that growing to
  // it moves nothing (a permutation leaves the columns without room).
  void reserve(std::size_t entity_count) {
    for (auto& [type, entry] : components_) entry.column->reserve(entity_count);
  }

  template <class C>
  C& add_component() {
    auto [it, inserted] = components_.try_emplace(std::type_index(typeid(C)));
    if (inserted) {
      it->second = {std::make_unique<C>(), C::key};
      it->second.column->resize(count_);
      if (auto saved = saved_.find(C::key); saved != saved_.end()) {
        restore_column(*it->second.column, C::key, saved->second);
        saved_.erase(saved);
      }
    }
    return static_cast<C&>(*it->second.column);
  }

  template <class C>
  C& component() {
    auto it = components_.find(std::type_index(typeid(C)));
    if (it != components_.end()) return static_cast<C&>(*it->second.column);
    if (saved_.count(C::key)) return add_component<C>();
    throw std::logic_error(std::string("world has no component '") + C::key + "'");
  }
  template <class C>
  const C& component() const {
    return const_cast<World*>(this)->component<C>();
  }
  template <class C>
  bool has_component() const {
    return components_.count(std::type_index(typeid(C))) != 0 || saved_.count(C::key) != 0;
  }

  template <class R, class... Args>
  R& emplace_resource(Args&&... args) {
    auto holder = std::make_shared<R>(std::forward<Args>(args)...);
    R& ref = *holder;
    resources_[std::type_index(typeid(R))] = std::move(holder);
    return ref;
  }
  template <class R>
  R& resource() {
    auto it = resources_.find(std::type_index(typeid(R)));
    if (it == resources_.end()) throw std::logic_error(std::string("world has no resource '") + R::key + "'");
    return *static_cast<R*>(it->second.get());
  }
  template <class R>
  const R& resource() const {
    return const_cast<World*>(this)->resource<R>();
  }
  template <class R>
  bool has_resource() const {
    return resources_.count(std::type_index(typeid(R))) != 0;
  }

  // Reorders every component column (to sort particles in space) and tells
  // every listener, so whatever holds particle indices can follow. A system
  // that may call it declares Access::writes_every_component().
  void permute(const std::vector<std::uint32_t>& order) {
    if (order.size() != count_) throw std::logic_error("permutation size differs from entity count");
    for (auto& [type, entry] : components_) {
      entry.column->permute(order);
      // A large column's old copy goes back to the system before the next
      // column makes its own, so that the peak is one column, not all.
      if (entry.column->bytes_per_entity() * count_ >= large_column_bytes) return_freed_memory();
    }
    for (auto& [key, saved] : saved_) {
      std::vector<double> reordered(saved.data.size());
      for (std::size_t k = 0; k < order.size(); ++k)
        for (std::size_t a = 0; a < saved.width; ++a) reordered[k * saved.width + a] = saved.data[order[k] * saved.width + a];
      saved.data.swap(reordered);
    }
    for (auto& listener : permutation_listeners_) listener(order);
  }
  void on_permute(PermutationListener listener) { permutation_listeners_.push_back(std::move(listener)); }

  std::size_t column_count() const { return components_.size(); }

  std::size_t component_bytes_per_entity() const {
    std::size_t bytes = 0;
    for (const auto& [type, entry] : components_) bytes += entry.column->bytes_per_entity();
    return bytes;
  }

  // Every column as "<key>" (values) and "<key>.width" (values per particle).
  StateMap save_columns() const {
    StateMap out;
    for (const auto& [type, entry] : components_) {
      out[entry.key] = entry.column->save();
      out[std::string(entry.key) + ".width"] = {static_cast<double>(entry.column->values_per_entity())};
    }
    for (const auto& [key, saved] : saved_) {
      out[key] = saved.data;
      out[key + ".width"] = {static_cast<double>(saved.width)};
    }
    return out;
  }

  // Replaces every column with checkpointed data for `entity_count` particles;
  // each becomes typed when first asked for.
  void restore_columns(std::size_t entity_count, const StateMap& columns) {
    components_.clear();
    saved_.clear();
    count_ = entity_count;
    for (const auto& [name, values] : columns) {
      if (name.size() > 6 && name.compare(name.size() - 6, 6, ".width") == 0) continue;
      const auto width_entry = columns.find(name + ".width");
      if (width_entry == columns.end() || width_entry->second.size() != 1 || !(width_entry->second[0] >= 1) ||
          width_entry->second[0] > 64)
        throw std::invalid_argument("checkpoint column '" + name + "' has no valid width");
      const auto width = static_cast<std::size_t>(width_entry->second[0]);
      if (values.size() != width * entity_count)
        throw std::invalid_argument("checkpoint column '" + name + "' holds " + std::to_string(values.size()) +
                                    " values, expected " + std::to_string(width * entity_count));
      saved_[name] = {width, values};
    }
  }

 private:
  // Columns from this size up may come from the heap rather than from pages
  // of their own (glibc raises its mmap threshold up to 32 MiB).
  static constexpr std::size_t large_column_bytes = std::size_t{1} << 20;
  struct SavedColumn {
    std::size_t width = 1;
    std::vector<double> data;
  };
  void restore_column(ColumnBase& column, const char* key, const SavedColumn& saved) const {
    if (saved.width != column.values_per_entity())
      throw std::invalid_argument(std::string("checkpoint column '") + key + "' has " + std::to_string(saved.width) +
                                  " values per particle, this run expects " +
                                  std::to_string(column.values_per_entity()));
    column.restore(saved.data);
  }

  struct Entry {
    std::unique_ptr<ColumnBase> column;
    const char* key = "";
  };
  std::size_t count_;
  std::unordered_map<std::type_index, Entry> components_;
  std::map<std::string, SavedColumn> saved_;
  std::unordered_map<std::type_index, std::shared_ptr<void>> resources_;
  std::vector<PermutationListener> permutation_listeners_;
};

}  // namespace granflow
