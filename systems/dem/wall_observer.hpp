#pragma once
// The walls over time, at each output: wall_position, each wall's position
// along its normal (x0 + A sin(omega t) for a moving wall; a divider's
// plane), and wall_force, the normal force the spheres press each wall with
// at the last force evaluation (for the floor of a bed at rest, its weight),
// in the order of the configuration's walls.

#include <string>
#include <vector>

#include "components/clock.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/dem/contact_forces.hpp"

namespace granflow::dem {

inline const SystemDescription observe_dem_walls_description{
    "observe_dem_walls", "each wall's position along its normal and the normal force the spheres press it with"};

template <int D>
class DemWallObserver : public SystemOf<Reads<Clock, DemInteractions<D>>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<Clock, DemInteractions<D>>, Writes<>>::View;
  std::string name() const override { return "observe_dem_walls"; }
  // The walls' forces are the whole system's on every rank.
  bool observes_by_rank() const override { return true; }
  Access access() const override {
    return View::access()
        .writes_observable("wall_position", unit::length)
        .writes_observable("wall_force", unit::force);
  }
  void run_on(View view) override {
    const auto& in = view.template read<DemInteractions<D>>();
    const double t = view.template read<Clock>().time;
    std::vector<double> position;
    for (const DemWall& w : in.walls) position.push_back(w.divider ? w.rest : w.position(t));
    std::vector<double> force = in.wall_force;
    force.resize(in.walls.size(), 0.0);
    auto& store = view.observables();
    store.set("wall_position", std::move(position));
    store.set("wall_force", std::move(force));
  }
};

}  // namespace granflow::dem
