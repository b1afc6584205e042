#pragma once
// The SDE node of a scenario graph: advances every particle of an ensemble of
// independent Langevin / UDSBM particles (systems/sde/sde_model.hpp) in
// fixed steps up to the next output time. Particles are independent, so each
// step is one tbb::parallel_for over blocks of particles; the Wiener
// increments are Philox draws keyed by (sde_noise, seed, step, particle), so
// the trajectories do not depend on the thread count or block size.
//
// Schemes: Euler-Maruyama exactly as in seed 000 (eqs. 2.92, 2.110), or the
// exact Ornstein-Uhlenbeck velocity update between two half drifts (the
// BAOAB splitting with no forces), which is exact in the velocity
// distribution at any step and keeps the MSD accurate at steps where
// Euler-Maruyama overshoots the velocity variance by 1/(1 - gamma h / 2).

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/rng.hpp"
#include "engine/run_control.hpp"
#include "engine/stream_ids.hpp"
#include "engine/system.hpp"
#include "engine/world.hpp"
#include "systems/sde/sde_model.hpp"

namespace granflow::sde {

enum class Scheme { euler_maruyama, exact_ou };

// One step of particle i, all D components; `normal` draws N(0, 1).
template <int D, class Normal>
GRANFLOW_HD inline void step_particle(double* x, double* v, const SdeModel& model, Scheme scheme, double t, double h,
                                      const OrnsteinUhlenbeck& ou, Normal&& normal) {
  if (scheme == Scheme::euler_maruyama) {
    const double gamma = model.friction(t), diffusivity = model.diffusivity(t);
    for (int a = 0; a < D; ++a) euler_maruyama_step(x[a], v[a], gamma, diffusivity, h, normal());
  } else {
    for (int a = 0; a < D; ++a) drift_ou_drift_step(x[a], v[a], ou, h, normal());
  }
}

template <int D>
class SdeAdvance : public System {
 public:
  // `after_step(step)` runs after every step (e.g. to feed an on-the-fly correlator).
  SdeAdvance(SdeModel model, Scheme scheme, double dt, std::uint64_t seed,
             std::function<void(std::int64_t)> after_step = {})
      : model_(model), scheme_(scheme), dt_(dt), seed_(seed), after_step_(std::move(after_step)) {}

  std::string name() const override { return "sde_advance"; }
  Access access() const override {
    return {{RunControl::key}, {Position<D>::key, Velocity<D>::key, Clock::key}};
  }

  void run(World& world) override {
    auto& clock = world.resource<Clock>();
    const double target = world.resource<RunControl>().target_time;
    // Steps are counted, not times summed, so output times land on steps exactly.
    while (static_cast<double>(clock.step + 1) * dt_ <= target * (1.0 + 1e-12)) {
      step(world, clock.step);
      ++clock.step;
      clock.time = static_cast<double>(clock.step) * dt_;
      if (after_step_) after_step_(clock.step);
    }
  }

  void step(World& world, std::int64_t step_index) {
    auto* x = world.component<Position<D>>().data();
    auto* v = world.component<Velocity<D>>().data();
    const double t = static_cast<double>(step_index) * dt_;
    const OrnsteinUhlenbeck ou = exact_velocity_update(model_, t, dt_);
    const SdeModel model = model_;
    const Scheme scheme = scheme_;
    const double h = dt_;
    const std::uint64_t seed = seed_;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, world.size(), 4096), [=](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        Philox random(stream::sde_noise, seed, static_cast<std::uint64_t>(step_index), i);
        step_particle<D>(x[i].data(), v[i].data(), model, scheme, t, h, ou, [&] { return random.normal(); });
      }
    });
  }

  double dt() const { return dt_; }

 private:
  SdeModel model_;
  Scheme scheme_;
  double dt_;
  std::uint64_t seed_;
  std::function<void(std::int64_t)> after_step_;
};

}  // namespace granflow::sde
