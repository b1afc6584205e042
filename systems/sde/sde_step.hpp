#pragma once
// The SDE node of a scenario graph: advances every particle of an ensemble of
// independent Langevin / UDSBM particles (systems/sde/sde_model.hpp) in
// fixed steps, one per run() (the Runner repeats it up to the next output). Particles are independent, so each
// step is one tbb::parallel_for over blocks of particles; the Wiener
// increments are Philox draws keyed by (sde_noise, seed, step, particle), so
// the trajectories do not depend on the thread count or block size.
//
// Noise: one Philox4x32-10 call per particle and step gives four normals
// (systems/sde/gaussian_noise.hpp), of which D are used.
//
// Schemes: Euler-Maruyama (Kloeden & Platen 1992), or the
// exact Ornstein-Uhlenbeck velocity update between two half drifts (the
// BAOAB splitting with no forces), which is exact in the velocity
// distribution at any step and keeps the MSD accurate at steps where
// Euler-Maruyama overshoots the velocity variance by 1/(1 - gamma h / 2).

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/run/run_control.hpp"
#include "systems/sde/sde_kernel.hpp"
#include "systems/sde/sde_model.hpp"

namespace granflow::sde {

inline const SystemDescription sde_advance_description{"sde_advance", "one Langevin / UDSBM step of independent particles (Euler-Maruyama or exact OU), parallel_for"};

template <int D>
class SdeAdvance : public SystemOf<Reads<>, Writes<Position<D>, Velocity<D>, Clock>> {
 public:
  using View = typename SystemOf<Reads<>, Writes<Position<D>, Velocity<D>, Clock>>::View;
  SdeAdvance(SdeModel model, Scheme scheme, double dt, std::uint64_t seed)
      : model_(model), scheme_(scheme), dt_(dt), seed_(seed) {}

  std::string name() const override { return "sde_advance"; }

  // One step; the Runner calls it until its target step.
  void run_on(View view) override {
    auto& clock = view.template write<Clock>();
    step(view.template write<Position<D>>(), view.template write<Velocity<D>>(), clock.step);
    clock.advance(dt_);
  }

  void step(World& world, std::int64_t step_index) {
    step(world.component<Position<D>>(), world.component<Velocity<D>>(), step_index);
  }
  void step(Position<D>& position, Velocity<D>& velocity, std::int64_t step_index) {
    // Eigen's fixed-size vectors are D packed doubles: the columns are flat arrays.
    double* x = position.data()->data();
    double* v = velocity.data()->data();
    const StepInput input{model_, scheme_, static_cast<double>(step_index) * dt_, dt_, seed_,
                          static_cast<std::uint64_t>(step_index)};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, position.size(), 4096), [=](const auto& range) {
      sde_step_range<D>(x, v, range.begin(), range.end(), input);
    });
  }

  double dt() const { return dt_; }

 private:
  SdeModel model_;
  Scheme scheme_;
  double dt_;
  std::uint64_t seed_;
};

}  // namespace granflow::sde
