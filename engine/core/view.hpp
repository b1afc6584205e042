#pragma once
// What a system may touch, as a type: View<Reads<...>, Writes<...>> hands
// out the listed columns and resources of a World and nothing else. A read
// of a type the view does not list, or a write of one it lists only as
// read, does not compile, and the view's access() is the declaration the
// Schedule orders systems by, so the two cannot disagree. SystemOf<...>
// derives a system's access from its view (EnTT's organizer reads the same
// from function signatures).
//
//   class Thermostat : public SystemOf<Reads<Mass>, Writes<Velocity<3>, SrdCells<3>>> {
//     void run_on(View view) override { view.write<Velocity<3>>() ... }
//   };

#include <cstdint>
#include <type_traits>
#include <vector>

#include "engine/core/access.hpp"
#include "engine/core/observed_part.hpp"
#include "engine/core/system.hpp"
#include "engine/core/world.hpp"

namespace granflow {

template <class... T>
struct Reads {};
// Listed in Writes<...>: the system may reorder the particles, which moves
// every column (World::permute), and so conflicts with every system that
// touches one.
struct EveryColumn {};
template <class... T>
struct Writes {};

template <class R, class W>
class View;

template <class... R, class... W>
class View<Reads<R...>, Writes<W...>> {
 public:
  // Implicit, so that setup code and tests may hand a World to a helper that
  // takes a view: the helper's signature still says what it touches.
  View(World& world) : world_(world) {}  // NOLINT(google-explicit-constructor)
  // A view that writes nothing may be taken of a const World (setup code and
  // writers that read the state outside the schedule).
  View(const World& world)  // NOLINT(google-explicit-constructor)
    requires(sizeof...(W) == 0)
      : world_(const_cast<World&>(world)) {}

  // The declaration this view stands for.
  static Access access() {
    Access access;
    (add_read<R>(access), ...);
    (add_write<W>(access), ...);
    return access;
  }

  template <class T>
  const T& read() const {
    static_assert(readable<T>, "View::read of a type the system does not declare (add it to Reads<...>)");
    return get<T>();
  }
  template <class T>
  T& write() {
    static_assert(writable<T>, "View::write of a type the system does not declare as written (add it to Writes<...>)");
    return get<T>();
  }
  // Reorders the particles: afterwards particle k is the one that was order[k].
  void permute(const std::vector<std::uint32_t>& order) {
    static_assert(listed<EveryColumn, W...>, "View::permute needs EveryColumn in Writes<...>");
    world_.permute(order);
  }
  // No particles, and their columns' memory given back (World::release).
  void release() {
    static_assert(listed<EveryColumn, W...>, "View::release needs EveryColumn in Writes<...>");
    world_.release();
  }
  // Whether the World holds an optional column or resource the view lists.
  template <class T>
  bool has() const {
    static_assert(readable<T>, "View::has of a type the system does not declare");
    if constexpr (std::is_base_of_v<ColumnBase, T>)
      return world_.template has_component<T>();
    else
      return world_.template has_resource<T>();
  }
  // A view of fewer columns, for a helper that declares its own (it can
  // take no more than this view lists, and write only what this one writes).
  template <class... R2, class... W2>
  operator View<Reads<R2...>, Writes<W2...>>() const {
    static_assert((readable<R2> && ...), "narrowing a View to read a type it does not list");
    static_assert((writable<W2> && ...), "narrowing a View to write a type it does not write");
    return View<Reads<R2...>, Writes<W2...>>(world_);
  }

  std::size_t size() const { return world_.size(); }
  // The observables this round: which names a system writes is declared by
  // name (Access::writes_observable), not by type, and the store checks
  // nothing; the columns and resources are what the view guards.
  ObservableStore& observables() const { return world_.template resource<ObservableStore>(); }
  // The part of the system the World holds (engine/core/observed_part.hpp):
  // an observer that runs by rank totals its sums through it.
  const ObservedPart& part() const {
    static const ObservedPart whole;
    return world_.template has_resource<ObservedPart>() ? world_.template resource<ObservedPart>() : whole;
  }

 private:
  template <class T, class... L>
  static constexpr bool listed = (std::is_same_v<T, L> || ...);
  template <class T>
  static constexpr bool any_column = std::is_base_of_v<ColumnBase, T> && listed<EveryColumn, W...>;
  template <class T>
  static constexpr bool readable = listed<T, R..., W...> || any_column<T>;
  template <class T>
  static constexpr bool writable = listed<T, W...> || any_column<T>;

  template <class T>
  static void add_read(Access& access) {
    access.reads<T>();
  }
  template <class T>
  static void add_write(Access& access) {
    if constexpr (std::is_same_v<T, EveryColumn>)
      access.writes_every_component();
    else
      access.writes<T>();
  }

  template <class T>
  T& get() const {
    if constexpr (std::is_base_of_v<ColumnBase, T>)
      return world_.template component<T>();
    else
      return world_.template resource<T>();
  }

  World& world_;
};

// A system that runs on a View: its access is the view's (a subclass adds
// the observables it writes by overriding access() and extending
// View::access()).
template <class R, class W>
class SystemOf : public System {
 public:
  using View = granflow::View<R, W>;
  Access access() const override { return View::access(); }
  void run(World& world) final { run_on(View(world)); }
  // Named apart from run(World&) so that a subclass does not hide it.
  virtual void run_on(View view) = 0;
};

}  // namespace granflow
