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
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/dem/neighbour_list.hpp"

namespace granflow::dem {

inline const SystemDescription dem_kick_drift_description{
    "dem_kick_drift", "velocity Verlet: half kick and drift of every sphere, periodic axes wrapped (parallel_for)"};
inline const SystemDescription dem_kick_description{"dem_kick", "velocity Verlet: the second half kick"};

// w += T dt / 2I for every sphere of a world whose spheres rotate.
template <int D>
void kick_rotation(View<Reads<Torque, Mass, Radius, NeighbourList<D>>, Writes<AngularVelocity>> view, double dt) {
  if (!view.template has<AngularVelocity>()) return;
  auto& w = view.template write<AngularVelocity>();
  const auto& torque = view.template read<Torque>();
  const auto& m = view.template read<Mass>();
  const auto& r = view.template read<Radius>();
  const ThreadDomains domains = sphere_domains<D>(view);
  for_each_sphere_run(domains, [&](std::size_t, std::size_t from, std::size_t to) {
    for (std::size_t i = from; i < to; ++i)
      w[i] += (0.5 * dt / (0.4 * m[i] * r[i] * r[i])) * torque[i];
  });
}

template <int D>
using DemKickDriftBase = SystemOf<Reads<Force<D>, Torque, Mass, Radius, Box<D>>,
                                  Writes<Position<D>, Velocity<D>, ImageCount<D>, AngularVelocity, Clock, NeighbourList<D>>>;

template <int D>
class DemKickDrift : public DemKickDriftBase<D> {
 public:
  using View = typename DemKickDriftBase<D>::View;
  explicit DemKickDrift(double dt) : dt_(dt) {}
  std::string name() const override { return "dem_kick_drift"; }
  void run_on(View view) override {
    auto& clock = view.template write<Clock>();
    clock.advance(dt_);
    auto& x = view.template write<Position<D>>();
    auto& v = view.template write<Velocity<D>>();
    const auto& f = view.template read<Force<D>>();
    const auto& m = view.template read<Mass>();
    const auto& box = view.template read<Box<D>>();
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
        view.template has<ImageCount<D>>() ? view.template write<ImageCount<D>>().values.data()->data() : nullptr;
    const double* const fs = f.values.data()->data();
    // With the lists built, each run of spheres also measures how far they
    // have moved since, while their positions are in cache: the lists' skin
    // test then has no pass of its own.
    NeighbourList<D>* nl = view.template has<NeighbourList<D>>() ? &view.template write<NeighbourList<D>>() : nullptr;
    if (nl && !(nl->built() && nl->reference.size() == view.size())) nl = nullptr;
    std::atomic<double> moved{0.0};
    const ThreadDomains domains = sphere_domains<D>(view);
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
    kick_rotation<D>(view, dt);
  }

 private:
  double dt_;
};

template <int D>
using DemKickBase = SystemOf<Reads<Force<D>, Torque, Mass, Radius, NeighbourList<D>>, Writes<Velocity<D>, AngularVelocity>>;

template <int D>
class DemKick : public DemKickBase<D> {
 public:
  using View = typename DemKickBase<D>::View;
  explicit DemKick(double dt) : dt_(dt) {}
  std::string name() const override { return "dem_kick"; }
  void run_on(View view) override {
    auto& v = view.template write<Velocity<D>>();
    const auto& f = view.template read<Force<D>>();
    const auto& m = view.template read<Mass>();
    const double dt = dt_;
    const ThreadDomains domains = sphere_domains<D>(view);
    for_each_sphere_run(domains, [&](std::size_t, std::size_t from, std::size_t to) {
      for (std::size_t i = from; i < to; ++i) v[i] += (0.5 * dt / m[i]) * f[i];
    });
    kick_rotation<D>(view, dt);
  }

 private:
  double dt_;
};

}  // namespace granflow::dem
