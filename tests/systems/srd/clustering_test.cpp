// The clustering measures against slower references and known fields: the
// per-axis transform against the D-dimensional DFT summed directly; S(k) of
// a Poisson gas within five standard errors of 1 in every shell; the
// correlation length of a single density wave equal to its wave length; the
// cluster labelling of hand-made grids, across the periodic edges.

#include "systems/srd/clustering.hpp"

#include <gtest/gtest.h>

#include <complex>
#include <numbers>
#include <random>
#include <vector>

namespace granflow::srd {
namespace {

template <int D>
std::vector<double> direct_power(const CellGridShape<D>& grid, const std::vector<double>& values) {
  std::vector<double> out(values.size());
  const auto index = [&](std::size_t c, int a) { return (c / grid.stride(a)) % static_cast<std::size_t>(grid.cells[a]); };
  for (std::size_t k = 0; k < values.size(); ++k) {
    std::complex<double> sum = 0.0;
    for (std::size_t c = 0; c < values.size(); ++c) {
      double phase = 0.0;
      for (int a = 0; a < D; ++a)
        phase += 2.0 * std::numbers::pi * static_cast<double>(index(k, a) * index(c, a)) / grid.cells[a];
      sum += values[c] * std::polar(1.0, -phase);
    }
    out[k] = std::norm(sum);
  }
  return out;
}

TEST(Clustering, PerAxisTransformIsTheDirectTransform) {
  std::mt19937_64 engine(3);
  std::uniform_real_distribution<double> uniform(0.0, 5.0);
  const CellGridShape<3> grid3{{4, 5, 6}};
  std::vector<double> values3(grid3.size());
  for (auto& v : values3) v = uniform(engine);
  const auto fast3 = power_spectrum<3>(grid3, values3), slow3 = direct_power<3>(grid3, values3);
  for (std::size_t k = 0; k < fast3.size(); ++k) EXPECT_NEAR(fast3[k], slow3[k], 1e-9 * (1 + slow3[k])) << k;
  const CellGridShape<2> grid2{{6, 8}};
  std::vector<double> values2(grid2.size());
  for (auto& v : values2) v = uniform(engine);
  const auto fast2 = power_spectrum<2>(grid2, values2), slow2 = direct_power<2>(grid2, values2);
  for (std::size_t k = 0; k < fast2.size(); ++k) EXPECT_NEAR(fast2[k], slow2[k], 1e-9 * (1 + slow2[k])) << k;
}

// Each mode's |F|^2 / N of Poisson counts is exponentially distributed with
// mean 1, so a shell of m modes has standard error about 1 / sqrt(m) per
// configuration; 40 configurations are averaged.
TEST(Clustering, PoissonGasHasUnitStructureFactor) {
  const CellGridShape<3> grid{{16, 16, 16}};
  std::mt19937_64 engine(5);
  std::uniform_int_distribution<std::size_t> cell(0, grid.size() - 1);
  const int configurations = 40;
  const double particles = 10.0 * grid.size();
  StructureFactor mean;
  for (int k = 0; k < configurations; ++k) {
    std::vector<double> counts(grid.size(), 0.0);
    for (int i = 0; i < particles; ++i) counts[cell(engine)] += 1.0;
    const auto s = shell_structure_factor<3>(grid, power_spectrum<3>(grid, counts), particles);
    if (mean.value.empty()) mean = StructureFactor{s.k, std::vector<double>(s.value.size(), 0.0)};
    for (std::size_t j = 0; j < s.value.size(); ++j) mean.value[j] += s.value[j] / configurations;
  }
  ASSERT_EQ(mean.value.size(), 8u);
  EXPECT_NEAR(mean.k[0], 2.0 * std::numbers::pi / 16.0, 1e-15);
  for (std::size_t j = 0; j < mean.value.size(); ++j) {
    // Modes in shell j: about 4 pi j^2 (at least 6 for j = 1).
    const double modes = std::max(6.0, 4.0 * std::numbers::pi * (j + 1.0) * (j + 1.0));
    EXPECT_NEAR(mean.value[j], 1.0, 5.0 / std::sqrt(modes * configurations)) << "shell " << j + 1;
  }
}

TEST(Clustering, CorrelationLengthOfADensityWaveIsItsWaveLength) {
  for (const int wave : {2, 4, 8}) {
    const CellGridShape<2> grid{{32, 32}};
    std::vector<double> counts(grid.size());
    for (std::size_t c = 0; c < counts.size(); ++c)
      counts[c] = 10.0 * (1.0 + std::cos(2.0 * std::numbers::pi * static_cast<double>(c % 32) / (32.0 / wave)));
    const auto s = shell_structure_factor<2>(grid, power_spectrum<2>(grid, counts), 10.0 * counts.size());
    EXPECT_NEAR(correlation_length(s), 32.0 / wave, 1e-9);
  }
}

TEST(Clustering, ClustersAreFaceConnectedAcrossPeriodicEdges) {
  const CellGridShape<2> grid{{6, 4}};
  // x fastest; '#' above the threshold of 2:
  //   y=0  # . . . . #      one cluster across the x edge (3 + 4 + 5 = 12)
  //   y=1  . . # . . .      a single cell (7), touching the next one only diagonally
  //   y=2  . . . # . .      a single cell (2.5)
  //   y=3  # . . . . .      joins the first across the y edge
  std::vector<double> counts(grid.size(), 1.0);
  counts[0] = 3.0;
  counts[5] = 4.0;
  counts[18] = 5.0;
  counts[8] = 7.0;
  counts[15] = 2.5;
  const auto sizes = cluster_sizes<2>(grid, counts, 2.0);
  ASSERT_EQ(sizes.size(), 3u);
  EXPECT_EQ(sizes[0], 12.0);
  EXPECT_EQ(sizes[1], 7.0);
  EXPECT_EQ(sizes[2], 2.5);
  EXPECT_TRUE(cluster_sizes<2>(grid, counts, 10.0).empty());
}

}  // namespace
}  // namespace granflow::srd
