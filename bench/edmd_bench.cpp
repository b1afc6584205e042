// Event-driven hard spheres: time per collision and memory per particle.
//
//   build/bench/edmd_bench                       all cases
//   build/bench/edmd_bench --benchmark_filter=Elastic/10000/300
//
// Elastic/N/eta*1000: elastic periodic 3D gas, equilibrated for 5 collisions
// per particle before timing. Cooling/N: the same at packing fraction 0.065
// with restitution 0.8, timed from the start of cooling over two decades of
// temperature, so the calendar must keep up with a falling event rate.

#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <numbers>

#include "systems/edmd/event_driven_gas.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/edmd/kinetic_theory.hpp"
#include "tests/scenario_schema.hpp"

namespace {

using namespace granflow;

Config gas_config(std::int64_t count, double eta, double restitution) {
  Config config(scenario_schema("haff_cooling"));
  config.set("system.count", count);
  config.set("system.radius", theory::radius_for_packing_fraction<3>(static_cast<double>(count), eta, 1.0));
  config.set("initial.velocity", std::string("maxwell_boltzmann"));
  config.set("initial.temperature", 1.0);
  config.set("collision.restitution", restitution);
  return config;
}

void report(benchmark::State& state, double collisions, double seconds, std::size_t bytes) {
  state.counters["us_per_collision"] = 1e6 * seconds / collisions;
  state.counters["collisions_per_s"] = collisions / seconds;
  state.counters["bytes_per_particle"] = static_cast<double>(bytes);
}

void Elastic(benchmark::State& state) {
  const auto count = state.range(0);
  const double eta = static_cast<double>(state.range(1)) / 1000.0;
  World world;
  edmd::build_gas<3>(world, gas_config(count, eta, 1.0), 1);
  edmd::EventDrivenGas<3> gas(world, edmd::CollisionParameters{});
  gas.start(0.0);
  edmd::AdvanceLimits limits;
  limits.max_pair_collisions = static_cast<std::uint64_t>(5 * count / 2);
  gas.advance(INFINITY, limits);
  double collisions = 0, seconds = 0;
  for (auto _ : state) {
    const auto before = gas.statistics().pair_collisions;
    limits.max_pair_collisions = before + static_cast<std::uint64_t>(std::max<std::int64_t>(count, 200000));
    const auto start = std::chrono::steady_clock::now();
    gas.advance(INFINITY, limits);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    collisions += static_cast<double>(gas.statistics().pair_collisions - before);
  }
  report(state, collisions, seconds, gas.bytes_per_particle());
}

void Cooling(benchmark::State& state) {
  const auto count = state.range(0);
  double collisions = 0, seconds = 0;
  std::size_t bytes = 0;
  double cooled = 0;
  for (auto _ : state) {
    state.PauseTiming();
    World world;
    edmd::build_gas<3>(world, gas_config(count, 0.065, 0.8), 1);
    edmd::EventDrivenGas<3> gas(world, edmd::CollisionParameters::from(gas_config(count, 0.065, 0.8)));
    gas.start(0.0);
    const double energy0 = gas.kinetic_energy();
    edmd::AdvanceLimits limits;
    limits.min_kinetic_energy = 1e-2 * energy0;
    state.ResumeTiming();
    const auto start = std::chrono::steady_clock::now();
    gas.advance(INFINITY, limits);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    collisions += static_cast<double>(gas.statistics().pair_collisions);
    bytes = gas.bytes_per_particle();
    cooled = gas.kinetic_energy() / energy0;
  }
  report(state, collisions, seconds, bytes);
  state.counters["final_energy_fraction"] = cooled;
}

}  // namespace

BENCHMARK(Elastic)
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {65, 300}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3)
    ->UseRealTime();
BENCHMARK(Cooling)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
