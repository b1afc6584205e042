#pragma once
// SRD streaming: every particle moves ballistically for one time step (or on
// the exact parabola of a constant body force), reflected by the walls it
// meets (srd_walls.hpp), back into the periodic box along the other axes,
// through the Lees-Edwards planes where the box is sheared. It also advances
// the clock: the step number keys the step's random numbers in the systems
// that follow.

#include <tbb/parallel_for.h>

#include <array>
#include <atomic>
#include <cmath>

#include "components/clock.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription srd_streaming_description{
    "srd_streaming", "x += v dt in the periodic box, Lees-Edwards shear planes along y (parallel_for)"};

template <int D>
class SrdStreaming : public System {
 public:
  // shear_rate: du_x/dy imposed through the Lees-Edwards planes (0: none);
  // acceleration: a constant body force per mass (gravity). Walls are the
  // SrdCells' own; Lees-Edwards planes do not combine with walls or a force.
  SrdStreaming(double dt, double shear_rate, std::array<double, D> acceleration = {})
      : dt_(dt), shear_rate_(shear_rate), acceleration_(acceleration) {}

  std::string name() const override { return "srd_streaming"; }

  // The Lees-Edwards state at `time`: the upper image's velocity and its
  // displacement, in [0, L_x).
  static void set_shear(SrdCells<D>& cells, double rate, double time) {
    if (D < 2 || rate == 0.0) return;
    cells.shear.velocity = rate * cells.length[1];
    cells.shear.offset = std::fmod(cells.shear.velocity * time, cells.length[0]);
  }
  Access access() const override { return Access{}.writes<Position<D>, Velocity<D>, Clock, SrdCells<D>>(); }

  void run(World& world) override {
    auto& clock = world.resource<Clock>();
    auto& cells = world.resource<SrdCells<D>>();
    const double start = clock.time;
    ++clock.step;
    clock.time = static_cast<double>(clock.step) * dt_;
    set_shear(cells, shear_rate_, clock.time);
    double* x = world.component<Position<D>>().data()->data();
    double* v = world.component<Velocity<D>>().data()->data();
    const Shear shear = cells.shear;
    const double* length = cells.length.data();
    const double dt = dt_;
    bool forced = false;
    for (double g : acceleration_) forced |= g != 0.0;
    if (cells.walls.empty() && !forced) {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, world.size(), 4096), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) stream_particle<D>(x + D * i, v + D * i, dt, length, shear);
      });
      return;
    }
    const Wall* walls = cells.walls.data();
    const int wall_count = static_cast<int>(cells.walls.size());
    const unsigned bounded = cells.bounded;
    const double* g = acceleration_.data();
    std::atomic<std::uint64_t> reflections{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, world.size(), 4096), [&](const auto& range) {
      std::uint64_t here = 0;
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        here += static_cast<std::uint64_t>(stream_between_walls<D>(x + D * i, v + D * i, g, start, dt, walls, wall_count));
        for (int a = 0; a < D; ++a)
          if (!(bounded & (1u << a))) x[D * i + a] = wrapped(x[D * i + a], length[a]);
      }
      reflections += here;
    });
    cells.wall_reflections += reflections.load();
  }

 private:
  double dt_;
  double shear_rate_;
  std::array<double, D> acceleration_;
};

}  // namespace granflow::srd
