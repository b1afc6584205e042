#pragma once
// Velocity Verlet for soft spheres, split around the force evaluation:
// DemKickDrift (v += F dt / 2m, x += v dt, periodic axes wrapped, the clock
// advanced) before the neighbour lists and forces, DemKick (v += F dt / 2m)
// after. Symplectic without damping: at restitution 1 the energy error stays
// bounded and scales as dt^2. The dampers see the half-step velocity. Where
// the spheres rotate (tangential friction), both kicks also turn their
// angular velocity by T dt / 2I with I = (2/5) m r^2, the moment of inertia
// of a solid sphere.

#include <tbb/parallel_for.h>


#include "components/angular_velocity.hpp"
#include "components/clock.hpp"
#include "components/force.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/torque.hpp"
#include "components/velocity.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"
#include "systems/dem/neighbour_list.hpp"

namespace granflow::dem {

inline const SystemDescription dem_kick_drift_description{
    "dem_kick_drift", "velocity Verlet: half kick and drift of every sphere, periodic axes wrapped (parallel_for)"};
inline const SystemDescription dem_kick_description{"dem_kick", "velocity Verlet: the second half kick"};

// w += T dt / 2I for every sphere of a world whose spheres rotate.
inline void kick_rotation(World& world, double dt) {
  if (!world.has_component<AngularVelocity>()) return;
  auto& w = world.component<AngularVelocity>();
  const auto& torque = world.component<Torque>();
  const auto& m = world.component<Mass>();
  const auto& r = world.component<Radius>();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, world.size(), 2048), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) w[i] += (0.5 * dt / (0.4 * m[i] * r[i] * r[i])) * torque[i];
  });
}

template <int D>
class DemKickDrift : public System {
 public:
  explicit DemKickDrift(double dt) : dt_(dt) {}
  std::string name() const override { return "dem_kick_drift"; }
  Access access() const override {
    return Access{}
        .reads<Force<D>, Torque, Mass, Radius, DemBox<D>>()
        .template writes<Position<D>, Velocity<D>, AngularVelocity, Clock>();
  }
  void run(World& world) override {
    auto& clock = world.resource<Clock>();
    ++clock.step;
    clock.time = static_cast<double>(clock.step) * dt_;
    auto& x = world.component<Position<D>>();
    auto& v = world.component<Velocity<D>>();
    const auto& f = world.component<Force<D>>();
    const auto& m = world.component<Mass>();
    const auto& box = world.resource<DemBox<D>>();
    const double dt = dt_;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, world.size(), 2048), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        v[i] += (0.5 * dt / m[i]) * f[i];
        x[i] += dt * v[i];
        box.wrap(x[i]);
      }
    });
    kick_rotation(world, dt);
  }

 private:
  double dt_;
};

template <int D>
class DemKick : public System {
 public:
  explicit DemKick(double dt) : dt_(dt) {}
  std::string name() const override { return "dem_kick"; }
  Access access() const override {
    return Access{}.reads<Force<D>, Torque, Mass, Radius>().template writes<Velocity<D>, AngularVelocity>();
  }
  void run(World& world) override {
    auto& v = world.component<Velocity<D>>();
    const auto& f = world.component<Force<D>>();
    const auto& m = world.component<Mass>();
    const double dt = dt_;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, world.size(), 2048), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) v[i] += (0.5 * dt / m[i]) * f[i];
    });
    kick_rotation(world, dt);
  }

 private:
  double dt_;
};

}  // namespace granflow::dem
