// shaken_bed, short: the flux over the divider accounts exactly for the
// change of the spheres on the left (every crossing is counted once), and
// the energy the floor injected less what the contacts dissipated matches
// the change of kinetic, potential and elastic energy to within 3 % of the
// injected energy (the ledger integrates the powers by the trapezoidal
// rule over the steps; measured 0.65 % at the default dt = t_c / 50); the
// packing-fraction profiles against height hold every sphere once. A bed
// whose state is broken mid-run (a sphere shot through the lid; energy
// from nowhere) stops with the watchdog's diagnosis.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "components/velocity.hpp"
#include "engine/io/h5md_reader.hpp"
#include "engine/run/run.hpp"
#include "engine/run/runner.hpp"
#include "tests/scenario_schema.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

std::string scratch(const std::string& name) {
  // Per process (two checkouts' tests may run at once), removed at exit.
  static const ScratchDirectory scratch_directory("granflow_dem_scenarios_");
  const auto& dir = scratch_directory.path;
  return (dir / (name + ".h5md")).string();
}

TEST(ShakenBed, FluxAccountsForTheAsymmetryAndTheEnergyBalances) {
  Config config(scenario_schema("shaken_bed"));
  config.set("run.t_stop", 20.0);
  config.set("output.average_after", 10.0);
  RunOptions options;
  options.output_path = scratch("shaken_bed");
  options.progress = false;
  options.handle_signals = false;
  ASSERT_EQ(run_scenario(*scenario_registry().find("shaken_bed"), config, options), 0);
  H5mdReader file(options.output_path);
  const auto a = file.doubles("/observables/asymmetry/value").values;
  const auto lr = file.doubles("/observables/flux_left_to_right/value").values;
  const auto rl = file.doubles("/observables/flux_right_to_left/value").values;
  const double n = 300;
  double net = 0.0, crossings = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    net += rl[k] - lr[k];
    crossings += rl[k] + lr[k];
    // N_L(t) - N_L(0) = crossings right to left minus left to right, so far.
    ASSERT_NEAR(0.5 * n * (a[k] - a[0]), net, 1e-9) << "output " << k;
  }
  EXPECT_GT(crossings, 10.0);
  const auto get = [&](const char* name) { return file.doubles(std::string("/observables/") + name + "/value").values; };
  const auto kinetic = get("kinetic_energy"), potential = get("potential_energy"), elastic = get("elastic_energy");
  const auto injected = get("energy_injected"), dissipated = get("energy_dissipated");
  const std::size_t last = kinetic.size() - 1;
  const double change = kinetic[last] + potential[last] + elastic[last] - kinetic[0] - potential[0] - elastic[0];
  std::printf("energy: change %.2f, injected %.2f - dissipated %.2f = %.2f\n", change, injected[last], dissipated[last],
              injected[last] - dissipated[last]);
  EXPECT_GT(injected[last], 0.0);
  EXPECT_GT(dissipated[last], 0.0);
  EXPECT_NEAR(change, injected[last] - dissipated[last], 0.03 * injected[last]);
  // The packing-fraction profiles hold every sphere once: the sum over both
  // compartments' layers (10 x 4 cross-sections, layers one diameter thick)
  // of fraction times layer volume is N times a sphere's volume.
  const auto left = file.doubles("/observables/packing_fraction_profile_left/value");
  const auto right = file.doubles("/observables/packing_fraction_profile_right/value");
  const std::size_t layers = left.values.size() / kinetic.size();
  for (std::size_t k = 0; k < kinetic.size(); ++k) {
    double volume = 0.0;
    for (std::size_t q = 0; q < layers; ++q) volume += 40.0 * (left.values[k * layers + q] + right.values[k * layers + q]);
    ASSERT_NEAR(volume, n * std::acos(-1.0) / 6.0, 1e-9) << "output " << k;
  }
  for (double t : file.doubles("/observables/temperature_profile_left/value").values) ASSERT_GE(t, 0.0);
  // The time-averaged profiles, sampled twenty times per shaking period
  // after output.average_after = 10, hold every sphere once as well.
  const auto left_mean = file.doubles("/results/packing_fraction_profile_mean_left").values;
  const auto right_mean = file.doubles("/results/packing_fraction_profile_mean_right").values;
  ASSERT_EQ(left_mean.size(), layers);
  double volume = 0.0;
  for (std::size_t q = 0; q < layers; ++q) volume += 40.0 * (left_mean[q] + right_mean[q]);
  EXPECT_NEAR(volume, n * std::acos(-1.0) / 6.0, 1e-9);
  // The walls (x-, x+, y-, y+, floor, ceiling, divider): the floor at
  // A sin(2 pi f t) at every output, the divider at x = 10; the floor, which
  // carries the spheres, is pressed down on average (a contact's force may
  // be briefly attractive at its end, so single values may be negative).
  const auto time = file.doubles("/observables/wall_position/time").values;
  const auto position = file.doubles("/observables/wall_position/value").values;
  const auto force = file.doubles("/observables/wall_force/value").values;
  ASSERT_EQ(position.size(), 7 * time.size());
  ASSERT_EQ(force.size(), 7 * time.size());
  double floor_force = 0.0;
  for (std::size_t k = 0; k < time.size(); ++k) {
    ASSERT_NEAR(position[7 * k + 4], 0.5 * std::sin(2.0 * std::acos(-1.0) * 2.5 * time[k]), 1e-12) << "output " << k;
    ASSERT_EQ(position[7 * k + 6], 10.0);
    floor_force += force[7 * k + 4] / static_cast<double>(time.size());
  }
  EXPECT_GT(floor_force, 0.0);
}

// shaken_bed built in memory, for a test to break its state.
struct BedInMemory {
  Config config{scenario_schema("shaken_bed")};
  Profiler profiler;
  std::unique_ptr<Run> run;
  BedInMemory() {
    config.set("run.t_stop", 5.0);
    config.set("output.average_after", 1.0);
    run = std::make_unique<Run>(config, profiler, 1, 0, nullptr, nullptr);
    scenario_registry().find("shaken_bed")->build(*run);
    run->prepare();
  }
  Velocity<3>& v() { return run->world().component<Velocity<3>>(); }
};

TEST(ShakenBed, ASphereShotThroughTheLidStopsTheRunAtOnce) {
  BedInMemory bed;
  bed.v()[17][2] = 1e30;
  const RunOutcome outcome = bed.run->execute(nullptr);
  EXPECT_EQ(outcome.kind, RunOutcome::Kind::failed);
  EXPECT_NE(outcome.reason.find("went through a wall: z = "), std::string::npos) << outcome.reason;
  EXPECT_NE(outcome.reason.find("(step 1)"), std::string::npos) << outcome.reason;
}

TEST(ShakenBed, EnergyFromNowhereStopsTheRunAtTheNextOutput) {
  BedInMemory bed;
  bool kicked = false;
  const RunOutcome outcome = bed.run->execute(nullptr, [&] {
    if (kicked) return;
    for (auto& v : bed.v().values) v *= 30.0;  // after the first output: nothing books it
    kicked = true;
  });
  EXPECT_EQ(outcome.kind, RunOutcome::Kind::failed);
  EXPECT_NE(outcome.reason.find("the step created"), std::string::npos) << outcome.reason;
  EXPECT_NEAR(bed.run->clock().time, 1.0, bed.run->derived("dt")) << "the next output after t = 0";
}

}  // namespace
}  // namespace granflow
