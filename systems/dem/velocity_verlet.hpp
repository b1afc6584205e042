#pragma once
// Velocity Verlet for soft spheres, split around the force evaluation:
// DemKickDrift (v += F dt / 2m, x += v dt, periodic axes wrapped, the clock
// advanced) before the neighbour lists and forces, DemKick (v += F dt / 2m)
// after. Symplectic without damping: at restitution 1 the energy error stays
// bounded and scales as dt^2. The dampers see the half-step velocity. Where
// the spheres rotate (tangential friction), both kicks also turn their
// angular velocity by T dt / 2I with I = (2/5) m r^2, the moment of inertia
// of a solid sphere.

#include <array>
#include <atomic>

#include "components/angular_velocity.hpp"
#include "components/clock.hpp"
#include "components/force.hpp"
#include "components/image_count.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/torque.hpp"
#include "components/velocity.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/world.hpp"
#include "systems/dem/neighbour_list.hpp"

namespace granflow::dem {

inline const SystemDescription dem_kick_drift_description{
    "dem_kick_drift", "velocity Verlet: half kick and drift of every sphere, periodic axes wrapped (parallel_for)"};
inline const SystemDescription dem_kick_description{"dem_kick", "velocity Verlet: the second half kick"};

// w += T dt / 2I for every sphere of a world whose spheres rotate.
template <int D>
void kick_rotation(World& world, double dt) {
  if (!world.has_component<AngularVelocity>()) return;
  auto& w = world.component<AngularVelocity>();
  const auto& torque = world.component<Torque>();
  const auto& m = world.component<Mass>();
  const auto& r = world.component<Radius>();
  const ThreadDomains domains = sphere_domains<D>(world);
  for_each_sphere_run(domains, [&](std::size_t, std::size_t from, std::size_t to) {
    for (std::size_t i = from; i < to; ++i)
      w[i] += (0.5 * dt / (0.4 * m[i] * r[i] * r[i])) * torque[i];
  });
}

template <int D>
class DemKickDrift : public System {
 public:
  explicit DemKickDrift(double dt) : dt_(dt) {}
  std::string name() const override { return "dem_kick_drift"; }
  Access access() const override {
    return Access{}
        .reads<Force<D>, Torque, Mass, Radius, Box<D>, NeighbourList<D>>()
        .template writes<Position<D>, Velocity<D>, ImageCount<D>, AngularVelocity, Clock, NeighbourList<D>>();
  }
  void run(World& world) override {
    auto& clock = world.resource<Clock>();
    ++clock.step;
    clock.time = static_cast<double>(clock.step) * dt_;
    auto& x = world.component<Position<D>>();
    auto& v = world.component<Velocity<D>>();
    const auto& f = world.component<Force<D>>();
    const auto& m = world.component<Mass>();
    const auto& box = world.resource<Box<D>>();
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
    std::int32_t* const images =
        world.has_component<ImageCount<D>>() ? world.component<ImageCount<D>>().values.data()->data() : nullptr;
    const double* const fs = f.values.data()->data();
    // With the lists built, each run of spheres also measures how far they
    // have moved since, while their positions are in cache: the lists' skin
    // test then has no pass of its own.
    NeighbourList<D>* nl = world.has_resource<NeighbourList<D>>() ? &world.resource<NeighbourList<D>>() : nullptr;
    if (nl && !(nl->built() && nl->reference.size() == world.size())) nl = nullptr;
    std::atomic<double> moved{0.0};
    const ThreadDomains domains = sphere_domains<D>(world);
    // Images are counted where an axis is periodic; a parameter of the
    // template, so that a box without one carries no test for them.
    const auto drift = [&]<bool CountImages>(std::size_t from, std::size_t to) {
      for (std::size_t i = from; i < to; ++i) {
        const double kick = 0.5 * dt / m[i];
        for (int a = 0; a < D; ++a) {
          const std::size_t k = i * D + static_cast<std::size_t>(a);
          vs[k] += kick * fs[k];
          double p = xs[k] + dt * vs[k];
          const double below = p < 0.0 ? period[a] : 0.0;
          p += below;
          const double above = p >= length[a] ? period[a] : 0.0;
          p -= above;
          xs[k] = p;
          if constexpr (CountImages)
            images[k] += static_cast<std::int32_t>(above > 0.0) - static_cast<std::int32_t>(below > 0.0);
        }
      }
    };
    for_each_sphere_run(domains, [&](std::size_t, std::size_t from, std::size_t to) {
      if (images)
        drift.template operator()<true>(from, to);
      else
        drift.template operator()<false>(from, to);
      if (nl) raise_to(moved, largest_displacement_squared(x.values.data(), *nl, box, from, to));
    });
    if (nl) {
      nl->displacement_squared = moved;
      nl->displacement_step = clock.step;
    }
    kick_rotation<D>(world, dt);
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
    return Access{}
        .reads<Force<D>, Torque, Mass, Radius, NeighbourList<D>>()
        .template writes<Velocity<D>, AngularVelocity>();
  }
  void run(World& world) override {
    auto& v = world.component<Velocity<D>>();
    const auto& f = world.component<Force<D>>();
    const auto& m = world.component<Mass>();
    const double dt = dt_;
    const ThreadDomains domains = sphere_domains<D>(world);
    for_each_sphere_run(domains, [&](std::size_t, std::size_t from, std::size_t to) {
      for (std::size_t i = from; i < to; ++i) v[i] += (0.5 * dt / m[i]) * f[i];
    });
    kick_rotation<D>(world, dt);
  }

 private:
  double dt_;
};

}  // namespace granflow::dem
