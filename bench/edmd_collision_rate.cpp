// Time per collision of one elastic periodic 3D gas, for comparing two
// builds of the engine run alternately (this machine's speed drifts, so
// A/B comparisons interleave single runs of each build):
//
//   build/bench/edmd_collision_rate N PACKING_FRACTION COLLISIONS
//
// Equilibrates for 5 collisions per particle from Maxwell-Boltzmann, then
// times COLLISIONS collisions; prints microseconds per collision and the
// cell crossings and stale events per collision. Below a packing fraction of
// 0.35 the particles start at random positions; denser fluids start on a
// lattice melted by 20 elastic collisions per particle, and from 0.49 on
// (past freezing, where the lattice stays solid) from a compressed random
// packing relaxed elastically; none of that is timed either.

#include <fmt/format.h>

#include <chrono>
#include <cstdlib>

#include "systems/edmd/gas_setup.hpp"
#include "systems/edmd/kinetic_theory.hpp"
#include "tests/scenario_schema.hpp"

int main(int argc, char** argv) {
  using namespace granflow;
  if (argc != 4) {
    fmt::print(stderr, "usage: {} N PACKING_FRACTION COLLISIONS\n", argv[0]);
    return 2;
  }
  const long count = std::atol(argv[1]);
  const double eta = std::atof(argv[2]);
  const long collisions = std::atol(argv[3]);
  if (count < 2 || !(eta > 0 && eta <= 0.5) || collisions < 1) {
    fmt::print(stderr, "need N >= 2, 0 < PACKING_FRACTION <= 0.5, COLLISIONS >= 1\n");
    return 2;
  }
  Config config(scenario_schema("haff_cooling"));
  config.set("system.count", static_cast<std::int64_t>(count));
  config.set("system.radius", theory::radius_for_packing_fraction<3>(static_cast<double>(count), eta, 1.0));
  config.set("initial.velocity", std::string("maxwell_boltzmann"));
  if (eta >= 0.35) config.set("initial.placement", std::string(eta < 0.49 ? "lattice" : "compressed"));
  World world;
  edmd::build_gas<3>(world, config, static_cast<std::uint64_t>(config.integer("run.seed")));
  edmd::EventDrivenGas<3> gas(world, edmd::CollisionParameters{});
  gas.start(0.0);
  edmd::AdvanceLimits limits;
  limits.max_pair_collisions = static_cast<std::uint64_t>(5 * count / 2);
  gas.advance(INFINITY, limits);
  const auto before = gas.statistics();
  limits.max_pair_collisions = before.pair_collisions + static_cast<std::uint64_t>(collisions);
  const auto start = std::chrono::steady_clock::now();
  gas.advance(INFINITY, limits);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto& after = gas.statistics();
  const double done = static_cast<double>(after.pair_collisions - before.pair_collisions);
  fmt::print("us/collision {:.3f}  crossings/collision {:.2f}  stale/collision {:.2f}\n", 1e6 * seconds / done,
             static_cast<double>(after.cell_crossings - before.cell_crossings) / done,
             static_cast<double>(after.stale_events - before.stale_events) / done);
  return 0;
}
