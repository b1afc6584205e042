// What the Runner's time loop and the per-step Schedule cost per step.
//
//   build/bench/schedule_bench
//
// Chain/5: five trivial systems, each needing the one before (the
//   sequential fast path), stepped through Run::execute: the loop, the
//   trigger bookkeeping, the Schedule and the Profiler's timers; ns per step.
// Parallel/5: the same five systems declared independent, so each step runs
//   a oneTBB flow graph instead.
// SdeDirect/N and SdeRun/N: the SDE step of N particles in 3D (exact OU),
//   called in a plain loop or run as a Run's per-step schedule; the ratio of
//   their times per step is the schedule's overhead on a real step.

#include <benchmark/benchmark.h>

#include <memory>

#include "components/clock.hpp"
#include "engine/run/run.hpp"
#include "systems/sde/sde_step.hpp"
#include "systems/sde/sde_theory.hpp"

namespace {

using namespace granflow;

template <int K>
struct Counter {
  static constexpr const char* key = "counter";
  std::uint64_t value = 0;
};

// Reads the previous counter (or nothing) and writes its own; the last one advances the clock.
template <int K, bool Chain>
class Trivial : public System {
 public:
  std::string name() const override { return "trivial" + std::to_string(K); }
  Access access() const override {
    Access access;
    access.writes<Counter<K>>();
    if constexpr (Chain && K > 0) access.reads<Counter<K - 1>>();
    if constexpr (K == 4) access.writes<Clock>();
    return access;
  }
  void run(World& world) override {
    ++world.resource<Counter<K>>().value;
    if constexpr (K == 4) {
      auto& clock = world.resource<Clock>();
      ++clock.step;
      clock.time = static_cast<double>(clock.step);
    }
  }
};

template <bool Chain>
void Steps(benchmark::State& state) {
  constexpr std::int64_t steps = 100000;
  const Config config;
  for (auto _ : state) {
    Profiler profiler;
    Run run(config, profiler, 1, 0, nullptr, nullptr);
    run.world().emplace_resource<Counter<0>>();
    run.world().emplace_resource<Counter<1>>();
    run.world().emplace_resource<Counter<2>>();
    run.world().emplace_resource<Counter<3>>();
    run.world().emplace_resource<Counter<4>>();
    run.step<Trivial<0, Chain>>();
    run.step<Trivial<1, Chain>>();
    run.step<Trivial<2, Chain>>();
    run.step<Trivial<3, Chain>>();
    run.step<Trivial<4, Chain>>();
    run.stop_at_step(steps);
    run.prepare();
    run.execute(nullptr);
    benchmark::DoNotOptimize(run.clock().step);
  }
  state.counters["ns_per_step"] = benchmark::Counter(static_cast<double>(state.iterations() * steps) * 1e-9,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
void Chain(benchmark::State& state) { Steps<true>(state); }
void Parallel(benchmark::State& state) { Steps<false>(state); }
BENCHMARK(Chain)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(Parallel)->UseRealTime()->Unit(benchmark::kMillisecond);

std::int64_t steps_for(std::size_t count) { return count >= 1000000 ? 20 : static_cast<std::int64_t>(20000000 / count); }

void fill(World& world, std::size_t count) {
  world.resize(count);
  world.add_component<Position<3>>().values.assign(count, Vec<3>::Zero());
  world.add_component<Velocity<3>>().values.assign(count, Vec<3>(0.3, -0.2, 0.1));
}

const sde::SdeModel model = sde::model_from_gas(1000, 0.025, 0.8, 2.0 / 3.0, 1.0, 1.0);

void SdeDirect(benchmark::State& state) {
  const auto count = static_cast<std::size_t>(state.range(0));
  const std::int64_t steps = steps_for(count);
  World world;
  fill(world, count);
  sde::SdeAdvance<3> advance(model, sde::Scheme::exact_ou, 0.01, 1);
  std::int64_t step = 0;
  for (auto _ : state)
    for (std::int64_t k = 0; k < steps; ++k) advance.step(world, step++);
  state.counters["us_per_step"] = benchmark::Counter(static_cast<double>(step) * 1e-6,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void SdeRun(benchmark::State& state) {
  const auto count = static_cast<std::size_t>(state.range(0));
  const std::int64_t steps = steps_for(count);
  const Config config;
  std::int64_t total = 0;
  for (auto _ : state) {
    state.PauseTiming();
    Profiler profiler;
    auto run = std::make_unique<Run>(config, profiler, 1, 0, nullptr, nullptr);
    fill(run->world(), count);
    run->step<sde::SdeAdvance<3>>(model, sde::Scheme::exact_ou, 0.01, 1);
    run->stop_at_step(steps);
    run->prepare();
    state.ResumeTiming();
    run->execute(nullptr);
    total += steps;
  }
  state.counters["us_per_step"] = benchmark::Counter(static_cast<double>(total) * 1e-6,
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(SdeDirect)->Arg(1000)->Arg(10000)->Arg(1000000)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(SdeRun)->Arg(1000)->Arg(10000)->Arg(1000000)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
