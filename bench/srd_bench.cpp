// SRD stepping speed: particle-steps per second of the whole 3D periodic SRD
// step (streaming, grid shift, binning, cell reduction, rotation) at 10^6
// particles, n0 = 10 (46^3 cells), on 1 and 2 threads, and the time of each
// stage, and of one reordering (Sort). Bytes moved per particle-step, for
// the bandwidth comparison with sde_bench's Copy: the streaming reads
// positions and velocities and writes positions (72 B), the binning reads
// positions and writes cells (28 B), the reduction reads cells and
// velocities (28 B, and about a fifth again for blocks read by two ranges of
// cells), the rotation reads cells and velocities and writes velocities
// (52 B) with its cell records (96 B per cell, about 10 B per particle), the
// per-cell sums about 10 B, and a reordering every 5 steps (counting sort
// and the permutation of both columns, about 150 B) 30 B: about 235 B per
// particle-step (at dt = 1).
//
//   build/bench/srd_bench
//   SRD_REORDER=1 build/bench/srd_bench   # particles in cell order every step
//   SRD_DT=0.02 build/bench/srd_bench     # the time step of LAMMPS's benchmark input

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cstdlib>
#include <memory>
#include <vector>

#include "components/clock.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "systems/srd/cell_binning.hpp"
#include "systems/srd/cell_reduction.hpp"
#include "systems/srd/grid_shift.hpp"
#include "systems/srd/rotation.hpp"
#include "systems/srd/streaming.hpp"

namespace {

using namespace granflow;

constexpr int side = 46;

// SRD_DT sets the time step (default 1: mean free path about one cell at
// kT = 1; LAMMPS's benchmark input takes 0.02).
double time_step() {
  const char* text = std::getenv("SRD_DT");
  return text ? std::strtod(text, nullptr) : 1.0;
}
// SRD_REORDER sets the steps between reorderings (default: from the mean
// free path, as srd.reorder_interval = 0 does).
std::uint64_t reorder_interval() {
  const char* text = std::getenv("SRD_REORDER");
  return text ? std::strtoull(text, nullptr, 10) : srd::reorder_interval_for(time_step());
}
constexpr std::size_t per_cell = 10;

struct Fluid {
  World world;
  std::vector<std::unique_ptr<System>> stages;
  Fluid() {
    const std::size_t n = per_cell * side * side * side;
    world.resize(n);
    world.emplace_resource<Clock>();
    auto& x = world.add_component<Position<3>>();
    auto& v = world.add_component<Velocity<3>>();
    for (std::size_t i = 0; i < n; ++i) {
      Philox random(stream::srd_initial, 1, 0, i);
      for (int a = 0; a < 3; ++a) x[i][a] = random.uniform() * side;
      for (int a = 0; a < 3; ++a) v[i][a] = random.normal();
    }
    auto& cells = world.emplace_resource<srd::SrdCells<3>>(std::array<std::int32_t, 3>{side, side, side}, n);
    srd::SrdCellBinning<3>::sort(world, cells);  // as the scenarios start
    srd::RotationParameters p;
    p.angle_degrees = 130.0;
    stages.push_back(std::make_unique<srd::SrdStreaming<3>>(time_step(), 0.0));
    stages.push_back(std::make_unique<srd::SrdGridShift<3>>(1, true));
    stages.push_back(std::make_unique<srd::SrdCellBinning<3>>(reorder_interval()));
    stages.push_back(std::make_unique<srd::SrdCellReduction<3>>());
    stages.push_back(std::make_unique<srd::SrdRotation<3>>(p, 1));
  }
};

Fluid& fluid() {
  static Fluid f;
  return f;
}

void Step(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  Fluid& f = fluid();
  for (auto& s : f.stages) s->run(f.world);  // warm
  for (auto _ : state)
    for (auto& s : f.stages) s->run(f.world);
  state.counters["particle_steps_per_s"] = benchmark::Counter(
      static_cast<double>(f.world.size()) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(Step)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

void Stage(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  Fluid& f = fluid();
  const auto k = static_cast<std::size_t>(state.range(0));
  for (auto _ : state) {
    state.PauseTiming();
    for (std::size_t s = 0; s < k; ++s) f.stages[s]->run(f.world);
    state.ResumeTiming();
    f.stages[k]->run(f.world);
    state.PauseTiming();
    for (std::size_t s = k + 1; s < f.stages.size(); ++s) f.stages[s]->run(f.world);
    state.ResumeTiming();
  }
  state.SetLabel(f.stages[k]->name());
}
// A reordering: the counting sort, the permutation of the particle columns
// and the cells again (every srd.reorder_interval steps).
void Sort(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  Fluid& f = fluid();
  auto& cells = f.world.resource<srd::SrdCells<3>>();
  for (auto _ : state) srd::SrdCellBinning<3>::sort(f.world, cells);
}
BENCHMARK(Sort)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// The grid shift (stage 1) draws three numbers: too short to time this way.
BENCHMARK(Stage)->Arg(0)->Arg(2)->Arg(3)->Arg(4)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
