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

#include <array>

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
    // A sphere moves much less than a box length per step: one compare and
    // select each way puts it back, without a branch.
    std::array<double, D> length{}, period{};
    for (int a = 0; a < D; ++a) {
      length[a] = box.length[a];
      period[a] = box.periodic[a] ? box.length[a] : 0.0;
    }
    double* const xs = x.values.data()->data();
    double* const vs = v.values.data()->data();
    const double* const fs = f.values.data()->data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, world.size(), 4096), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const double kick = 0.5 * dt / m[i];
        for (int a = 0; a < D; ++a) {
          const std::size_t k = i * D + static_cast<std::size_t>(a);
          vs[k] += kick * fs[k];
          double p = xs[k] + dt * vs[k];
          p += p < 0.0 ? period[a] : 0.0;
          p -= p >= length[a] ? period[a] : 0.0;
          xs[k] = p;
        }
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
