// Soft-sphere DEM stepping speed: particle-steps per second of the vibrated
// bed (scenario vibrated_bed at LAMMPS's dt = 0.001: Hookean contacts,
// floor shaken at amplitude 0.5 and period 1, gravity 1) for a bed of
// 10 580 spheres (LAMMPS's shaken-bed input) and one of 10^5 (the same bed
// three times as wide each way, 72 x 72), on 1 and 2 threads. Each figure
// is the time of a run of T time units less that of the same run stopped
// after one step (placement and the first forces), so it counts the steps
// only; the
// runs with 1 and 2 threads alternate (this machine's speed drifts) and the
// median of the rounds is printed with its range.
//
//   build/bench/dem_bench [rounds] [T]     (default 3 rounds, T = 2)

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/run/runner.hpp"
#include "tests/scenario_schema.hpp"

namespace {

using namespace granflow;

struct Bed {
  const char* name;
  std::int64_t count;
  std::vector<double> box, fill;
};

double seconds_of(const Bed& bed, double t_stop, int threads) {
  Config config(scenario_schema("vibrated_bed"));
  config.set("system.count", bed.count);
  config.set("system.box", bed.box);
  config.set("bed.fill", bed.fill);
  config.set("run.dt", 0.001);
  config.set("run.t_stop", t_stop);
  config.set("output.interval", t_stop);
  RunOptions options;
  options.output_path = (std::filesystem::temp_directory_path() / "granflow_dem_bench.h5md").string();
  options.progress = false;
  options.handle_signals = false;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  const auto start = std::chrono::steady_clock::now();
  if (run_scenario(*scenario_registry().find("vibrated_bed"), config, options) != 0) {
    fmt::print(stderr, "the vibrated bed did not run\n");
    std::exit(1);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const double t = argc > 2 ? std::max(0.01, std::atof(argv[2])) : 2.0;
  spdlog::set_level(spdlog::level::warn);
  const std::vector<Bed> beds = {
      {"10580 spheres, 24 x 24", 10580, {24, 24, 80}, {0, 22.5, 0, 22.5, 0.6, 20.5}},
      {"100000 spheres, 72 x 72", 100000, {72, 72, 80}, {0, 70, 0, 70, 0.6, 20.5}},
  };
  const auto steps = static_cast<double>(std::llround(t / 0.001));
  for (const Bed& bed : beds) {
    std::vector<double> rate[2], speedup;
    for (int round = 0; round < rounds; ++round) {
      double per_thread[2];
      for (int k = 0; k < 2; ++k) {
        // Alternate which thread count goes first.
        const int threads = (round + k) % 2 + 1;
        const double stepping = seconds_of(bed, t + 0.001, threads) - seconds_of(bed, 0.001, threads);
        per_thread[threads - 1] = static_cast<double>(bed.count) * steps / stepping;
        rate[threads - 1].push_back(per_thread[threads - 1]);
      }
      speedup.push_back(per_thread[1] / per_thread[0]);
    }
    for (int k = 0; k < 2; ++k)
      fmt::print("{}, {} thread{}: {:.3g} particle-steps/s (median of {}; {:.3g} to {:.3g})\n", bed.name, k + 1,
                 k ? "s" : "", median(rate[k]), rounds, *std::min_element(rate[k].begin(), rate[k].end()),
                 *std::max_element(rate[k].begin(), rate[k].end()));
    fmt::print("{}: speed-up on 2 threads {:.2f} (median; {:.2f} to {:.2f})\n", bed.name, median(speedup),
               *std::min_element(speedup.begin(), speedup.end()), *std::max_element(speedup.begin(), speedup.end()));
  }
  return 0;
}
