// The multiple-tau time-averaged MSD against a brute-force average over all
// time origins of stored trajectories: exact at the lags of the first level
// (which see every origin), within the statistical spread at the coarser
// levels (which see every 2^l-th origin), and the ergodicity-breaking
// parameter against its definition.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/core/rng.hpp"
#include "systems/observables/multiple_tau_msd.hpp"

namespace granflow {
namespace {

TEST(MultipleTauMsd, MatchesBruteForceTimeAverage) {
  constexpr std::size_t particles = 40, samples = 4000;
  constexpr int dim = 2;
  // Gaussian random walks: x[s][p][a].
  std::vector<std::vector<double>> x(samples, std::vector<double>(particles * dim, 0.0));
  for (std::size_t p = 0; p < particles; ++p) {
    Philox random(99, 5, 0, p);
    for (std::size_t s = 1; s < samples; ++s)
      for (int a = 0; a < dim; ++a) x[s][p * dim + a] = x[s - 1][p * dim + a] + random.normal();
  }
  MultipleTauMsd correlator(particles, dim, samples, 16, 2);
  for (const auto& sample : x) correlator.add(sample.data());
  const auto result = correlator.result();
  ASSERT_FALSE(result.lag.empty());
  for (std::size_t k = 0; k < result.lag.size(); ++k) {
    const auto lag = static_cast<std::size_t>(result.lag[k]);
    if (lag >= samples / 4) break;
    std::vector<double> per_particle(particles, 0.0);
    for (std::size_t p = 0; p < particles; ++p) {
      for (std::size_t s = 0; s + lag < samples; ++s)
        for (int a = 0; a < dim; ++a) {
          const double d = x[s + lag][p * dim + a] - x[s][p * dim + a];
          per_particle[p] += d * d;
        }
      per_particle[p] /= static_cast<double>(samples - lag);
    }
    double mean = 0.0, square = 0.0;
    for (double v : per_particle) {
      mean += v / particles;
      square += v * v / particles;
    }
    if (lag < 16) {
      EXPECT_NEAR(result.msd[k] / mean, 1.0, 1e-12) << "lag " << lag;
      EXPECT_NEAR(result.ergodicity_breaking[k], square / (mean * mean) - 1.0, 1e-9) << "lag " << lag;
    } else {
      // A random walk's MSD is 2 lag; fewer origins add scatter of order
      // sqrt(lag / samples) per particle, averaged over 40 particles.
      EXPECT_NEAR(result.msd[k] / mean, 1.0, 0.05) << "lag " << lag;
      EXPECT_NEAR(result.msd[k] / (dim * static_cast<double>(lag)), 1.0, 0.15) << "lag " << lag;
    }
  }
  // Lags are increasing and reach the run length.
  for (std::size_t k = 1; k < result.lag.size(); ++k) EXPECT_GT(result.lag[k], result.lag[k - 1]);
  EXPECT_GE(result.lag.back() * 2, static_cast<double>(samples) / 2);
}

}  // namespace
}  // namespace granflow
