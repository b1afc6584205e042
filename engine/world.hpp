#pragma once
// The World owns every particle component (one contiguous column per
// component type) and the singleton resources. Systems reach both by type.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <typeindex>
#include <unordered_map>
#include <vector>

namespace granflow {

// Type-erased view of a component column, so the World can resize and reorder
// every column without knowing its type.
class ColumnBase {
 public:
  virtual ~ColumnBase() = default;
  virtual void resize(std::size_t count) = 0;
  // new_values[k] = old_values[order[k]]
  virtual void permute(const std::vector<std::uint32_t>& order) = 0;
  virtual std::size_t bytes_per_entity() const = 0;
};

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
  void permute(const std::vector<std::uint32_t>& order) override {
    std::vector<T> reordered(order.size());
    for (std::size_t k = 0; k < order.size(); ++k) reordered[k] = values[order[k]];
    values.swap(reordered);
  }
  std::size_t bytes_per_entity() const override { return sizeof(T); }
};

class World {
 public:
  explicit World(std::size_t entity_count = 0) : count_(entity_count) {}
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  World(World&&) = default;
  World& operator=(World&&) = default;

  std::size_t size() const { return count_; }

  void resize(std::size_t entity_count) {
    count_ = entity_count;
    for (auto& [type, column] : components_) column->resize(count_);
  }

  template <class C>
  C& add_component() {
    auto [it, inserted] = components_.try_emplace(std::type_index(typeid(C)));
    if (inserted) {
      it->second = std::make_unique<C>();
      it->second->resize(count_);
    }
    return static_cast<C&>(*it->second);
  }

  template <class C>
  C& component() {
    auto it = components_.find(std::type_index(typeid(C)));
    if (it == components_.end())
      throw std::logic_error(std::string("world has no component '") + C::key + "'");
    return static_cast<C&>(*it->second);
  }
  template <class C>
  const C& component() const {
    return const_cast<World*>(this)->component<C>();
  }
  template <class C>
  bool has_component() const {
    return components_.count(std::type_index(typeid(C))) != 0;
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
    if (it == resources_.end())
      throw std::logic_error(std::string("world has no resource '") + R::key + "'");
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

  // Reorders every component column; used to sort particles in space.
  void permute(const std::vector<std::uint32_t>& order) {
    if (order.size() != count_) throw std::logic_error("permutation size differs from entity count");
    for (auto& [type, column] : components_) column->permute(order);
  }

  std::size_t component_bytes_per_entity() const {
    std::size_t bytes = 0;
    for (const auto& [type, column] : components_) bytes += column->bytes_per_entity();
    return bytes;
  }

 private:
  std::size_t count_;
  std::unordered_map<std::type_index, std::unique_ptr<ColumnBase>> components_;
  std::unordered_map<std::type_index, std::shared_ptr<void>> resources_;
};

}  // namespace granflow
