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

#include <type_traits>

#include "engine/core/access.hpp"
#include "engine/core/system.hpp"
#include "engine/core/world.hpp"

namespace granflow {

template <class... T>
struct Reads {};
template <class... T>
struct Writes {};

template <class R, class W>
class View;

template <class... R, class... W>
class View<Reads<R...>, Writes<W...>> {
 public:
  explicit View(World& world) : world_(world) {}

  // The declaration this view stands for.
  static Access access() { return Access{}.reads<R...>().template writes<W...>(); }

  template <class T>
  const T& read() const {
    static_assert(listed<T, R..., W...>, "View::read of a type the system does not declare (add it to Reads<...>)");
    return get<T>();
  }
  template <class T>
  T& write() {
    static_assert(listed<T, W...>, "View::write of a type the system does not declare as written (add it to Writes<...>)");
    return get<T>();
  }
  // Whether the World holds an optional column or resource the view lists.
  template <class T>
  bool has() const {
    static_assert(listed<T, R..., W...>, "View::has of a type the system does not declare");
    if constexpr (std::is_base_of_v<ColumnBase, T>)
      return world_.template has_component<T>();
    else
      return world_.template has_resource<T>();
  }
  std::size_t size() const { return world_.size(); }
  // The observables this round: which names a system writes is declared by
  // name (Access::writes_observable), not by type, and the store checks
  // nothing; the columns and resources are what the view guards.
  ObservableStore& observables() const { return world_.template resource<ObservableStore>(); }

 private:
  template <class T, class... L>
  static constexpr bool listed = (std::is_same_v<T, L> || ...);

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
