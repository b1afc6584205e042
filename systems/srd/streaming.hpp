#pragma once
// SRD streaming: every particle moves ballistically for one time step (or on
// the exact parabola of a constant body force), reflected by the walls it
// meets (srd_walls.hpp), back into the periodic box along the other axes,
// through the Lees-Edwards planes where the box is sheared; a particle that
// needs more reflections in a step than srd_walls.hpp allows stops the run
// (exit 3) instead of being put back unbooked. It also advances
// the clock: the step number keys the step's random numbers in the systems
// that follow.

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "components/clock.hpp"
#include "components/image_count.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/run/run_control.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

inline const SystemDescription srd_streaming_description{
    "srd_streaming", "x += v dt in the periodic box, Lees-Edwards shear planes along y (parallel_for)"};

// Why a run stops when particles needed more than most_reflections in one
// step (the CPU streaming and the device step say it alike).
inline std::string stranded_failure(double time, std::int64_t step, std::uint64_t stranded, double dt) {
  return fmt::format(
      "the SRD streaming failed at t = {:.6g} (step {}): {} particle(s) met the walls more than {} times in one step "
      "and could not be streamed exactly (their energy would go unbooked). A particle pressed onto a wall by the "
      "force hops 2 v / g apart, so a slow one hops without end; lower srd.time_step (now {:.4g}) or "
      "force.acceleration / shaking.gravity",
      time, step, stranded, most_reflections, dt);
}

// One particle's step where there are walls or a force: the exact flight
// between the walls (adding their work to *work where that is given), then
// back into the box along the axes whose bit is set in `periodic`, counted
// in its image where that is given. Returns its reflections
// (most_reflections: it could not be streamed exactly).
template <int D>
struct WalledFlight {
  const Wall* walls;
  int wall_count;
  unsigned periodic;
  BodyForce<D> force;
  double start, dt;
  const double* length;

  int operator()(double* x, double* v, std::int32_t* image, double* work) const {
    const double none[D] = {};
    const double* g = force.acts_at(x) ? force.acceleration : none;
    const int reflections = stream_between_walls<D>(x, v, g, start, dt, walls, wall_count, work);
    for (int a = 0; a < D; ++a)
      if (periodic & (1u << a)) {
        if (image) image[a] += static_cast<std::int32_t>(periods_out(x[a], length[a]));
        x[a] = wrapped(x[a], length[a]);
      }
    return reflections;
  }
};

template <int D>
class SrdStreaming : public SystemOf<Reads<>, Writes<Position<D>, Velocity<D>, ImageCount<D>, Clock, SrdCells<D>, RunControl>> {
 public:
  using View = typename SystemOf<Reads<>, Writes<Position<D>, Velocity<D>, ImageCount<D>, Clock, SrdCells<D>, RunControl>>::View;
  // shear_rate: du_x/dy imposed through the Lees-Edwards planes (0: none);
  // force: a constant body force per mass (gravity, or driving in a slab).
  // Walls are the SrdCells' own; Lees-Edwards planes do not combine with
  // walls or a force.
  SrdStreaming(double dt, double shear_rate, BodyForce<D> force = {})
      : dt_(dt), shear_rate_(shear_rate), force_(force) {}

  std::string name() const override { return "srd_streaming"; }

  // The Lees-Edwards state at `time`: the upper image's velocity and its
  // displacement, in [0, L_x).
  static void set_shear(SrdCells<D>& cells, double rate, double time) {
    if (D < 2 || rate == 0.0) return;
    cells.shear.velocity = rate * cells.length[1];
    cells.shear.offset = std::fmod(cells.shear.velocity * time, cells.length[0]);
  }

  void run_on(View view) override {
    auto& clock = view.template write<Clock>();
    auto& cells = view.template write<SrdCells<D>>();
    const double start = clock.time;
    clock.advance(dt_);
    set_shear(cells, shear_rate_, clock.time);
    double* x = view.template write<Position<D>>().data()->data();
    double* v = view.template write<Velocity<D>>().data()->data();
    // Counted only where the run writes particle frames (srd_frames.hpp).
    std::int32_t* images =
        view.template has<ImageCount<D>>() ? view.template write<ImageCount<D>>().values.data()->data() : nullptr;
    const Shear shear = cells.shear;
    const double* length = cells.length.data();
    const double dt = dt_;
    if (cells.walls.empty() && !force_.any()) {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, view.size(), 4096), [&](const auto& range) {
        if (images)
          for (std::size_t i = range.begin(); i != range.end(); ++i)
            stream_particle<D, true>(x + D * i, v + D * i, dt, length, shear, images + D * i);
        else
          for (std::size_t i = range.begin(); i != range.end(); ++i)
            stream_particle<D>(x + D * i, v + D * i, dt, length, shear);
      });
      return;
    }
    const WalledFlight<D> flight{cells.walls.data(), static_cast<int>(cells.walls.size()), ~cells.bounded, force_,
                                 start, dt, length};
    // Per fixed chunk of particles, so that the sum of the walls' work does
    // not depend on the thread count.
    constexpr std::size_t chunk = 4096;
    const std::size_t chunks = (view.size() + chunk - 1) / chunk;
    chunk_work_.assign(chunks, 0.0);
    chunk_reflections_.assign(chunks, 0);
    chunk_stranded_.assign(chunks, 0);
    double* chunk_work = cells.record_energy ? chunk_work_.data() : nullptr;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks), [&](const auto& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        std::uint64_t here = 0, stranded = 0;
        double* work = chunk_work ? chunk_work + k : nullptr;
        const std::size_t end = std::min(view.size(), (k + 1) * chunk);
        for (std::size_t i = k * chunk; i != end; ++i) {
          const int reflections = flight(x + D * i, v + D * i, images ? images + D * i : nullptr, work);
          here += static_cast<std::uint64_t>(reflections);
          stranded += reflections == most_reflections ? 1 : 0;
        }
        chunk_reflections_[k] = here;
        chunk_stranded_[k] = stranded;
      }
    });
    std::uint64_t stranded = 0;
    for (std::size_t k = 0; k < chunks; ++k) {
      cells.wall_reflections += chunk_reflections_[k];
      stranded += chunk_stranded_[k];
    }
    if (stranded > 0) view.template write<RunControl>().fail(stranded_failure(clock.time, clock.step, stranded, dt_));
    if (cells.record_energy) {
      double work = 0.0;
      for (double w : chunk_work_) work += w;
      cells.step_wall_work = cells.particle_mass * work;
    }
  }

 private:
  double dt_;
  double shear_rate_;
  BodyForce<D> force_;
  std::vector<double> chunk_work_;
  std::vector<std::uint64_t> chunk_reflections_;
  std::vector<std::uint64_t> chunk_stranded_;
};

}  // namespace granflow::srd
