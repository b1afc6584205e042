// GPU benchmark of the SRD step (systems/srd/srd_device.hpp): particle-steps per
// second for a 3D periodic fluid of n0 = 10 particles per cell at kT = 1,
// alpha = 130 deg, dt = 0.1 (the LAMMPS workload's mean free path is
// smaller; this one moves particles a tenth of a cell per step), with the
// grid shift and a reordering every 20 steps, for each particle count given
// (default 1e6 1e7 1e8); and the bytes a step moves per particle, from a
// count of what each kernel reads and writes, against the card's bandwidth
// as a device-to-device copy measures it.
//   granflow_srd_gpu_bench [particles ...]

#include <cuda_runtime.h>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "systems/srd/grid_shift.hpp"
#include "systems/srd/srd_device.hpp"

namespace {

using granflow::Philox;

// Copy bandwidth (read + write) of the card, in bytes per second.
double copy_bandwidth() {
  const std::size_t bytes = std::size_t{1} << 30;
  void *a = nullptr, *b = nullptr;
  if (cudaMalloc(&a, bytes) != cudaSuccess || cudaMalloc(&b, bytes) != cudaSuccess) return 0.0;
  cudaMemcpy(b, a, bytes, cudaMemcpyDeviceToDevice);
  cudaEvent_t start, stop;
  cudaEventCreate(&start);
  cudaEventCreate(&stop);
  cudaEventRecord(start);
  constexpr int repeats = 10;
  for (int k = 0; k < repeats; ++k) cudaMemcpy(b, a, bytes, cudaMemcpyDeviceToDevice);
  cudaEventRecord(stop);
  cudaEventSynchronize(stop);
  float ms = 0.0f;
  cudaEventElapsedTime(&ms, start, stop);
  cudaFree(a);
  cudaFree(b);
  return 2.0 * bytes * repeats / (1e-3 * ms);
}

// Bytes a periodic step moves per particle: streaming (x, v read and
// written, the cell written), the sort (the cells copied to the keys, the
// order written as 0..n-1, then per 8-bit digit of the 32-bit keys: keys and
// values read and written), the bounds (the sorted keys), the reduction
// (order and velocity), the collision (velocity read and written, the cell),
// the reordering's gathers once per `reorder` steps; per cell (shared by n0
// particles) its bounds, sums, matrix, clamp flag and mean written and read.
double bytes_per_particle_step(double n0, double reorder) {
  const double passes = 4;
  const double particle =
      (48 + 48 + 4) + (8 + 4 + passes * 16) + 4 + (4 + 24) + (24 + 24 + 4) + (48 + 48 + 4 + 4 + 4) / reorder;
  const double cell = (8 + 8) + (4 + 8 + 24 + 8) + (4 + 8 + 72 + 16) + (72 + 24);
  return particle + cell / n0;
}

}  // namespace

int main(int argc, char** argv) {
  if (const std::string why = granflow::device::srd_device_unavailable(); !why.empty()) {
    fmt::print(stderr, "granflow_srd_gpu_bench: {}\n", why);
    return 77;
  }
  std::vector<double> counts;
  for (int k = 1; k < argc; ++k) counts.push_back(std::atof(argv[k]));
  if (counts.empty()) counts = {1e6, 1e7, 1e8};
  cudaDeviceProp prop{};
  cudaGetDeviceProperties(&prop, 0);
  const double bandwidth = copy_bandwidth();
  fmt::print("device: {} ({:.0f} GB), copy bandwidth {:.0f} GB/s\n", prop.name, prop.totalGlobalMem / 1e9, bandwidth / 1e9);
  fmt::print("{:>12} {:>10} {:>16} {:>14} {:>12} {:>10}\n", "particles", "cells", "particle-steps/s", "bytes/p-step",
             "GB/s moved", "of copy");
  constexpr double n0 = 10.0, dt = 0.1;
  constexpr std::uint64_t reorder = 20, seed = 5;
  for (double wanted : counts) {
    const auto side = static_cast<std::int32_t>(std::llround(std::cbrt(wanted / n0)));
    const std::size_t cells = static_cast<std::size_t>(side) * side * side;
    const auto n = static_cast<std::size_t>(n0 * static_cast<double>(cells));
    granflow::device::SrdDeviceSetup s;
    s.dimension = 3;
    for (int a = 0; a < 3; ++a) {
      s.cells[a] = side;
      s.length[a] = side;
    }
    s.dt = dt;
    s.seed = seed;
    s.rotation.cos_alpha = std::cos(130.0 * std::acos(-1.0) / 180.0);
    s.rotation.sin_alpha = std::sin(130.0 * std::acos(-1.0) / 180.0);
    s.reorder_interval = reorder;
    std::vector<double> x(3 * n), v(3 * n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      Philox random(granflow::stream::srd_initial, seed, 0, i);
      for (int a = 0; a < 3; ++a) x[3 * i + a] = random.uniform() * side;
      for (int a = 0; a < 3; ++a) v[3 * i + a] = random.normal();
    });
    granflow::device::SrdDevice device(s, n);
    device.upload(x.data(), v.data());
    const auto run = [&](std::uint64_t first, std::uint64_t steps) {
      for (std::uint64_t step = first; step < first + steps; ++step) {
        granflow::device::SrdDeviceStep in;
        in.step = step;
        in.start_time = (step - 1) * dt;
        in.end_time = step * dt;
        std::array<double, 3> shift{};
        granflow::srd::SrdGridShift<3>::draw(shift, seed, step, true);
        for (int a = 0; a < 3; ++a) in.shift[a] = shift[a];
        device.step(in);
      }
    };
    run(1, 20);  // warm-up: the sort's scratch, the caches, a reordering
    const std::uint64_t steps = n >= 50'000'000 ? 40 : 200;
    const auto start = std::chrono::steady_clock::now();
    run(21, steps);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double rate = static_cast<double>(n) * static_cast<double>(steps) / seconds;
    const double bytes = bytes_per_particle_step(n0, reorder);
    fmt::print("{:>12.3g} {:>10} {:>16.3g} {:>14.0f} {:>12.0f} {:>9.0f}%\n", static_cast<double>(n), cells, rate, bytes,
               rate * bytes / 1e9, bandwidth > 0 ? 100.0 * rate * bytes / bandwidth : 0.0);
    for (const auto& e : device.profile())
      fmt::print("    {:<36} {:>8.3f} ms per call\n", e.system, 1e3 * e.total_seconds / static_cast<double>(e.calls));
  }
  return 0;
}
