// Sweep files: grid x zip x listed points in a defined order, fixed [set]
// overrides, repeats with distinct reproducible seeds, output names, and
// errors that name the problem; shards balanced by the runs' expected cost.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "engine/app/sweep_plan.hpp"
#include "engine/app/sweep_shards.hpp"
#include "tests/scratch_directory.hpp"

namespace granflow {
namespace {

std::string write_sweep(const std::string& name, const std::string& body) {
  // Per process (two checkouts' tests may run at once), removed at exit.
  static const ScratchDirectory scratch_directory("granflow_sweep_plan_test_");
  const auto& dir = scratch_directory.path;
  std::ofstream(dir / name) << "scenario_file = \"" << GRANFLOW_SOURCE_DIR << "/scenarios/haff_cooling.toml\"\n"
                            << body;
  return (dir / name).string();
}

TEST(SweepPlan, GridZipAndListCombineInOrder) {
  const auto file = write_sweep("combined.toml", R"(
repeats = 2
output = "out"
[set]
"system.count" = 300
[grid]
collision.restitution = [0.9, 0.5]
system.boundary = ["periodic", "reflecting"]
[zip]
"run.t_stop" = [1.0, 2.0]
"output.first" = [0.1, 0.2]
[[points]]
"collision.contact_time" = 1e-6
)");
  const SweepPlan plan = read_sweep_plan(file);
  EXPECT_EQ(plan.scenario, "haff_cooling");
  ASSERT_EQ(plan.parameter_values.size(), 2u * 2u * 2u * 1u);
  ASSERT_EQ(plan.runs.size(), 16u);
  EXPECT_EQ(plan.swept_keys, (std::vector<std::string>{"collision.restitution", "system.boundary", "run.t_stop",
                                                        "output.first", "collision.contact_time"}));
  // The first grid axis written varies slowest, then the zip; file order, not key order.
  EXPECT_EQ(plan.parameter_values[0], (std::vector<std::string>{"0.9", "periodic", "1", "0.1", "1e-06"}));
  EXPECT_EQ(plan.parameter_values[1], (std::vector<std::string>{"0.9", "periodic", "2", "0.2", "1e-06"}));
  EXPECT_EQ(plan.parameter_values[2], (std::vector<std::string>{"0.9", "reflecting", "1", "0.1", "1e-06"}));
  EXPECT_EQ(plan.parameter_values[7], (std::vector<std::string>{"0.5", "reflecting", "2", "0.2", "1e-06"}));
  const auto& last = plan.runs.back();
  EXPECT_EQ(last.parameter_point, 7u);
  EXPECT_EQ(last.repeat, 1u);
  const Config last_config = plan.run_config(plan.runs.size() - 1);
  EXPECT_EQ(last_config.integer("system.count"), 300);
  EXPECT_DOUBLE_EQ(last_config.real("collision.restitution"), 0.5);
  EXPECT_EQ(last_config.text("system.boundary"), "reflecting");
  EXPECT_EQ(last.output, std::filesystem::path("out") / "p007_r01.h5md");
  // Repeat 0 keeps the base seed; others differ from it and from each other, reproducibly.
  std::set<std::int64_t> seeds;
  for (std::size_t k = 0; k < plan.runs.size(); ++k) {
    const auto& run = plan.runs[k];
    EXPECT_EQ(plan.run_config(k).integer("run.seed"), run.seed);
    if (run.repeat == 0) {
      EXPECT_EQ(run.seed, 1);
    }
    seeds.insert(run.seed);
  }
  EXPECT_EQ(seeds.size(), 2u);
  EXPECT_EQ(repeat_seed(1, 1), read_sweep_plan(file).runs[1].seed);
  EXPECT_NE(repeat_seed(1, 1), repeat_seed(1, 2));
  EXPECT_NE(repeat_seed(1, 1), repeat_seed(2, 1));
  EXPECT_GE(repeat_seed(1, 7), 0);
}

TEST(SweepShards, TheCostKeysBalanceTheShards) {
  const auto file = write_sweep("cost.toml", R"(
cost = ["system.count", "run.t_stop"]
[set]
"run.t_stop" = 2.0
[grid]
"system.count" = [1000, 100, 400, 300, 200]
)");
  const SweepPlan plan = read_sweep_plan(file);
  ASSERT_EQ(plan.runs.size(), 5u);
  EXPECT_DOUBLE_EQ(plan.runs[0].cost, 2000.0);
  EXPECT_DOUBLE_EQ(plan.runs[1].cost, 200.0);
  // Longest first, each to the shard with less work: the large run alone,
  // the four others (800 + 600 + 400 + 200) together.
  EXPECT_EQ(shard_of_runs(plan, 2), (std::vector<std::size_t>{0, 1, 1, 1, 1}));
  // Without cost keys, by count: round robin.
  const auto even = read_sweep_plan(write_sweep("even.toml", R"(
[grid]
"system.count" = [1000, 100, 400, 300, 200]
)"));
  EXPECT_EQ(shard_of_runs(even, 3), (std::vector<std::size_t>{0, 1, 2, 0, 1}));
  // Every run in exactly one shard, for any count.
  for (std::size_t count : {1, 2, 5, 7}) {
    const auto shard = shard_of_runs(plan, count);
    for (std::size_t s : shard) EXPECT_LT(s, count);
  }
}

TEST(SweepShards, ShardTextIsIOverN) {
  const Shard shard = parse_shard("2/3");
  EXPECT_EQ(shard.index, 2u);
  EXPECT_EQ(shard.count, 3u);
  for (const char* bad : {"0/3", "4/3", "a/3", "3", "2/", "/3", "2/3x", "-1/3"})
    EXPECT_THROW(parse_shard(bad), ConfigError) << bad;
}

TEST(SweepPlan, ErrorsNameTheProblem) {
  const auto expect_error = [](const std::string& body, const std::string& needle) {
    try {
      read_sweep_plan(write_sweep("bad.toml", body));
      ADD_FAILURE() << "accepted: " << body;
    } catch (const ConfigError& error) {
      EXPECT_NE(std::string(error.what()).find(needle), std::string::npos) << error.what();
    }
  };
  expect_error("[grid]\ncollision.restitution = [0.5, 2.0]\n", "'collision.restitution' = 2 is out of range");
  expect_error("[zip]\na.b = [1, 2]\n", "unknown configuration key 'a.b'");
  expect_error("repeats = 2\n[grid]\nrun.seed = [1, 2]\n", "run.seed is swept explicitly");
  expect_error("summary = \"temperature\"\n", "summary must be an array");
  expect_error("points = [1, 2]\n", "[[points]] entries must be tables");
  expect_error("grid = 3\n", "[grid] must be a table");
  expect_error("output = 3\n", "output must be a directory name");
  // A grid of six lists of 10 values would be 10^6 points: refused before any is built.
  std::string wide = "[grid]\n";
  for (const char* key : {"system.count", "system.radius", "system.mass", "collision.restitution", "run.seed",
                          "initial.speed"})
    wide += std::string(key) + " = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n";
  expect_error(wide, "[grid] spans 1e+06 parameter points; at most 100000 are allowed");
  expect_error("repeats = 100000\n[grid]\nsystem.count = [100, 200, 300, 400, 500, 600, 700, 800, 900, 1000, 1100]\n",
               "runs; at most 1000000 are allowed");
}

}  // namespace
}  // namespace granflow
