#pragma once
// The SDE node of a scenario graph: advances every particle of an ensemble of
// independent Langevin / UDSBM particles (systems/sde/sde_model.hpp) in
// fixed steps up to the next output time. Particles are independent, so each
// step is one tbb::parallel_for over blocks of particles; the Wiener
// increments are Philox draws keyed by (sde_noise, seed, step, particle), so
// the trajectories do not depend on the thread count or block size.
//
// Noise: one Philox4x32-10 call per particle and step gives four normals
// (systems/sde/gaussian_noise.hpp), of which D are used.
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
#include "engine/run_control.hpp"
#include "engine/stream_ids.hpp"
#include "engine/system.hpp"
#include "engine/world.hpp"
#include "systems/sde/sde_kernel.hpp"
#include "systems/sde/sde_model.hpp"

namespace granflow::sde {

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
    // Eigen's fixed-size vectors are D packed doubles: the columns are flat arrays.
    double* x = world.component<Position<D>>().data()->data();
    double* v = world.component<Velocity<D>>().data()->data();
    const StepInput input{model_, scheme_, static_cast<double>(step_index) * dt_, dt_, seed_,
                          static_cast<std::uint64_t>(step_index)};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, world.size(), 4096), [=](const auto& range) {
      sde_step_range<D>(x, v, range.begin(), range.end(), input);
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
