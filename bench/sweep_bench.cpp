// Parallel speed-up of `granflow sweep`: the same sweep run with 1 and with
// 2 workers, alternately (this machine's speed drifts, so the two are
// interleaved rather than run in two blocks), into fresh directories.
//
//   build/bench/sweep_bench [SWEEP.toml] [rounds]
//   (default: scenarios/crater_mass_sweep.toml, 3 rounds)

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/app/sweep_plan.hpp"
#include "engine/app/sweep_runner.hpp"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace granflow;
  const std::string file = argc > 1 ? argv[1] : std::string(GRANFLOW_SOURCE_DIR) + "/scenarios/crater_mass_sweep.toml";
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
  spdlog::set_level(spdlog::level::warn);
  const auto scratch = std::filesystem::temp_directory_path() / "granflow_sweep_bench";
  std::vector<double> seconds[3];
  std::vector<double> ratios;
  for (int round = 0; round < rounds; ++round) {
    double pair[3] = {0, 0, 0};
    // Alternate which worker count goes first.
    for (int k = 0; k < 2; ++k) {
      const int workers = (round + k) % 2 + 1;
      std::filesystem::remove_all(scratch);
      const SweepPlan plan = read_sweep_plan(file, scratch.string());
      SweepOptions options;
      options.workers = workers;
      options.progress = false;
      const auto start = std::chrono::steady_clock::now();
      const int status = run_sweep(plan, options);
      pair[workers] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      seconds[workers].push_back(pair[workers]);
      fmt::print("round {}: {} worker{}: {:.2f} s ({} runs{})\n", round + 1, workers, workers > 1 ? "s" : "",
                 pair[workers], plan.runs.size(), status ? ", some stopped early" : "");
    }
    ratios.push_back(pair[1] / pair[2]);
  }
  std::filesystem::remove_all(scratch);
  fmt::print("median: 1 worker {:.2f} s, 2 workers {:.2f} s; speed-up per round:", median(seconds[1]),
             median(seconds[2]));
  for (double r : ratios) fmt::print(" {:.2f}", r);
  fmt::print("; median {:.2f}\n", median(ratios));
  return 0;
}
