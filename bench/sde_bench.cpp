// SDE stepping speed: particle-steps per second of the Langevin / UDSBM step
// in 3D on 1 and 2 threads, and a STREAM-like copy on the same threads, so
// the step's memory traffic can be put against what the machine moves.
//
//   build/bench/sde_bench
//   build/bench/sde_bench --benchmark_filter=Step
//
// Step/<scheme>/<threads>: 10^6 particles (48 MB of positions and
// velocities, far beyond the caches); scheme 0 = exact OU, 1 = Euler-Maruyama.
// Copy/<threads>: copies 64 MB between two arrays; bytes counted read + write.

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <vector>

#include "components/clock.hpp"
#include "engine/run/run_control.hpp"
#include "systems/sde/sde_step.hpp"
#include "systems/sde/sde_theory.hpp"

namespace {

using namespace granflow;

void Step(benchmark::State& state) {
  const auto scheme = state.range(0) == 0 ? sde::Scheme::exact_ou : sde::Scheme::euler_maruyama;
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(1)));
  constexpr std::size_t count = 1000000;
  World world(count);
  world.add_component<Position<3>>().values.assign(count, Vec<3>::Zero());
  world.add_component<Velocity<3>>().values.assign(count, Vec<3>(0.3, -0.2, 0.1));
  const sde::SdeModel model = sde::model_from_gas(1000, 0.025, 0.8, 2.0 / 3.0, 1.0, 1.0);
  sde::SdeAdvance<3> advance(model, scheme, 0.01, 1);
  std::int64_t step = 0;
  for (auto _ : state) advance.step(world, step++);
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(static_cast<double>(count) * static_cast<double>(step), benchmark::Counter::kIsRate);
  // Positions and velocities are read and written once per step.
  state.counters["bytes_per_s"] = benchmark::Counter(4.0 * 24.0 * static_cast<double>(count) * static_cast<double>(step),
                                                     benchmark::Counter::kIsRate);
}
BENCHMARK(Step)->ArgsProduct({{0, 1}, {1, 2}})->UseRealTime()->Unit(benchmark::kMillisecond);

void Copy(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  constexpr std::size_t count = 8 << 20;  // doubles: 64 MB per array
  std::vector<double> from(count, 1.0), to(count, 0.0);
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1 << 16), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) to[i] = from[i];
    });
    benchmark::DoNotOptimize(to.data());
  }
  state.counters["bytes_per_s"] = benchmark::Counter(2.0 * 8.0 * static_cast<double>(count) *
                                                         static_cast<double>(state.iterations()),
                                                     benchmark::Counter::kIsRate);
}
BENCHMARK(Copy)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
