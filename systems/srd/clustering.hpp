#pragma once
// Clustering of a periodic granular fluid, from the particle counts of the
// unshifted unit cells:
//   structure_factor        S(k) = |sum_c n_c exp(-i k.r_c)|^2 / N averaged over
//                           the modes of each shell k_j = j dk, j = 1 .. J
//                           (dk = 2 pi / the shortest box edge, J = half its
//                           cells); 1 at every k for a Poisson (ideal) gas
//   structure_factor_k      those k_j
//   correlation_length      L = 2 pi sum_j S_j / sum_j k_j S_j, the length of
//                           the density structure (its first-moment wave length)
//   cluster_count           clusters: face-connected cells (periodic) holding
//                           more than `threshold` n0 particles each
//   largest_cluster         the share of all particles in the largest one
//   cluster_size_mean       sum s^2 / sum s: the particles in the cluster of a
//                           particle picked at random among those in clusters
//   cluster_size_distribution  clusters of 2^b to 2^(b+1) - 1 particles, b = 0, 1, ...
// The counts and the sums run in a fixed order; the transform's lines are
// independent, so the values do not depend on the thread count. Over ranks
// each rank transforms its layers of the count field along the other axes;
// the writing rank puts the field together, transforms it along the slabs'
// axis and alone analyses it (and sets these observables).

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "components/position.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/srd/fourier_line.hpp"

namespace granflow::srd {

inline const SystemDescription observe_clustering_description{
    "observe_clustering", "structure factor, correlation length and cluster sizes of the density on the unit cells"};

// A D-dimensional grid of cell values, x fastest.
template <int D>
struct CellGridShape {
  std::array<std::int32_t, D> cells{};
  std::size_t size() const {
    std::size_t n = 1;
    for (auto c : cells) n *= static_cast<std::size_t>(c);
    return n;
  }
  std::size_t stride(int axis) const {
    std::size_t s = 1;
    for (int a = 0; a < axis; ++a) s *= static_cast<std::size_t>(cells[a]);
    return s;
  }
};

// The discrete Fourier transform of a field along one axis (lines in
// parallel, each by fourier_line.hpp). Cost N times the sum of the prime
// factors of the axis's edge L (N L where L is prime) for N cells.
template <int D>
void transform_axis(const CellGridShape<D>& grid, std::vector<std::complex<double>>& field, int axis) {
  const auto length = static_cast<std::size_t>(grid.cells[axis]);
  const std::size_t stride = grid.stride(axis);
  const FourierLine line_transform(length);
  const std::size_t lines = field.size() / length;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lines, 64), [&](const tbb::blocked_range<std::size_t>& range) {
    std::vector<std::complex<double>> out(length);
    for (std::size_t line = range.begin(); line != range.end(); ++line) {
      // The line's first cell: `line` counts the cells with this axis's index 0.
      const std::size_t below = line % stride, above = line / stride;
      const std::size_t first = below + above * stride * length;
      line_transform.transform(&field[first], stride, out.data());
      for (std::size_t m = 0; m < length; ++m) field[first + m * stride] = out[m];
    }
  });
}

inline std::vector<double> power_of(const std::vector<std::complex<double>>& field) {
  std::vector<double> power(field.size());
  for (std::size_t c = 0; c < field.size(); ++c) power[c] = std::norm(field[c]);
  return power;
}

// |F(k)|^2 of real cell values on every mode, by one discrete Fourier
// transform per axis.
template <int D>
std::vector<double> power_spectrum(const CellGridShape<D>& grid, const std::vector<double>& values) {
  std::vector<std::complex<double>> field(values.begin(), values.end());
  for (int axis = 0; axis < D; ++axis) transform_axis<D>(grid, field, axis);
  return power_of(field);
}

struct StructureFactor {
  std::vector<double> k, value;
};

// Shell averages of power / particles, shells j dk wide around k = j dk.
template <int D>
StructureFactor shell_structure_factor(const CellGridShape<D>& grid, const std::vector<double>& power, double particles) {
  std::int32_t shortest = grid.cells[0];
  for (auto c : grid.cells) shortest = std::min(shortest, c);
  const double dk = 2.0 * std::numbers::pi / shortest;
  const auto shells = static_cast<std::size_t>(shortest / 2);
  StructureFactor out;
  std::vector<double> sum(shells + 1, 0.0), modes(shells + 1, 0.0);
  for (std::size_t c = 0; c < power.size(); ++c) {
    double k2 = 0.0;
    std::size_t rest = c;
    for (int a = 0; a < D; ++a) {
      const auto length = static_cast<std::int64_t>(grid.cells[a]);
      auto m = static_cast<std::int64_t>(rest % static_cast<std::size_t>(length));
      rest /= static_cast<std::size_t>(length);
      if (2 * m > length) m -= length;
      const double k = 2.0 * std::numbers::pi * static_cast<double>(m) / static_cast<double>(length);
      k2 += k * k;
    }
    const auto shell = static_cast<std::size_t>(std::floor(std::sqrt(k2) / dk + 0.5));
    if (shell == 0 || shell > shells) continue;
    sum[shell] += power[c];
    modes[shell] += 1.0;
  }
  for (std::size_t j = 1; j <= shells; ++j) {
    out.k.push_back(static_cast<double>(j) * dk);
    out.value.push_back(modes[j] > 0 ? sum[j] / modes[j] / particles : 0.0);
  }
  return out;
}

inline double correlation_length(const StructureFactor& s) {
  double weight = 0.0, first = 0.0;
  for (std::size_t j = 0; j < s.k.size(); ++j) {
    weight += s.value[j];
    first += s.k[j] * s.value[j];
  }
  return first > 0 ? 2.0 * std::numbers::pi * weight / first : 0.0;
}

// The particles of each cluster (face-connected cells above `threshold`
// particles, periodic), in the order of their first cell.
template <int D>
std::vector<double> cluster_sizes(const CellGridShape<D>& grid, const std::vector<double>& counts, double threshold) {
  std::vector<std::int32_t> label(counts.size(), -1);
  std::vector<double> sizes;
  std::vector<std::size_t> stack;
  for (std::size_t seed = 0; seed < counts.size(); ++seed) {
    if (label[seed] >= 0 || counts[seed] <= threshold) continue;
    const auto id = static_cast<std::int32_t>(sizes.size());
    sizes.push_back(0.0);
    label[seed] = id;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      sizes.back() += counts[c];
      for (int a = 0; a < D; ++a) {
        const std::size_t stride = grid.stride(a);
        const auto length = static_cast<std::size_t>(grid.cells[a]);
        const std::size_t index = (c / stride) % length;
        for (const std::size_t next_index : {(index + 1) % length, (index + length - 1) % length}) {
          const std::size_t next = c + (next_index - index) * stride;  // unsigned wrap cancels
          if (label[next] < 0 && counts[next] > threshold) {
            label[next] = id;
            stack.push_back(next);
          }
        }
      }
    }
  }
  return sizes;
}

template <int D>
class ClusteringObserver : public SystemOf<Reads<Position<D>>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<Position<D>>, Writes<>>::View;
  // cells: the unit cells of the periodic box; threshold: a cluster cell
  // holds more than threshold n0 particles.
  ClusteringObserver(std::array<std::int32_t, D> cells, double n0, double threshold)
      : grid_{cells}, cut_(threshold * n0) {}

  std::string name() const override { return "observe_clustering"; }
  Access access() const override {
    return View::access()
        .writes_observable("structure_factor", unit::none)
        .writes_observable("structure_factor_k", "L-1")
        .writes_observable("correlation_length", unit::length)
        .writes_observable("cluster_count", unit::none)
        .writes_observable("largest_cluster", unit::none)
        .writes_observable("cluster_size_mean", unit::none)
        .writes_observable("cluster_size_distribution", unit::none);
  }

  // Each rank counts its particles on its layers of cells; the writing rank
  // puts the whole count field together and analyses it alone.
  bool observes_by_rank() const override { return true; }

  void run_on(View view) override {
    const auto& x = view.template read<Position<D>>();
    const std::size_t n = view.size();
    const ObservedPart& part = view.part();
    CellGridShape<D> mine = grid_;
    const int axis = part.axis();
    const std::int64_t low = part.layer_low();
    mine.cells[axis] = static_cast<std::int32_t>(part.layer_high(grid_.cells[axis]) - low);
    std::vector<double> counts(mine.size(), 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t c = 0;
      for (int a = 0; a < D; ++a) {
        const auto length = grid_.cells[a];
        auto index = static_cast<std::int64_t>(std::floor(x[i][a]));
        index = ((index % length) + length) % length;
        if (a == axis) index = std::clamp<std::int64_t>(index - low, 0, mine.cells[a] - 1);
        c += static_cast<std::size_t>(index) * mine.stride(a);
      }
      counts[c] += 1.0;
    }
    const auto particles = part.total(static_cast<double>(n));
    const std::vector<double> power = spectrum(part, mine, counts);
    counts = part.whole_field(std::move(counts), std::vector<std::int32_t>(grid_.cells.begin(), grid_.cells.end()), 1);
    if (!part.writes()) return;
    const StructureFactor s = shell_structure_factor<D>(grid_, power, particles);
    const std::vector<double> sizes = cluster_sizes<D>(grid_, counts, cut_);
    double largest = 0.0, sum = 0.0, squares = 0.0;
    std::vector<double> distribution(static_cast<std::size_t>(std::floor(std::log2(std::max(particles, 1.0)))) + 1, 0.0);
    for (double size : sizes) {
      largest = std::max(largest, size);
      sum += size;
      squares += size * size;
      const auto bin = static_cast<std::size_t>(std::floor(std::log2(size)));
      distribution[std::min(bin, distribution.size() - 1)] += 1.0;
    }
    auto& store = view.observables();
    store.set("structure_factor", s.value);
    store.set("structure_factor_k", s.k);
    store.set("correlation_length", correlation_length(s));
    store.set("cluster_count", static_cast<double>(sizes.size()));
    store.set("largest_cluster", particles > 0 ? largest / particles : 0.0);
    store.set("cluster_size_mean", sum > 0 ? squares / sum : 0.0);
    store.set("cluster_size_distribution", std::move(distribution));
  }

 private:
  // The power spectrum of the whole count field, on the writing rank. Over
  // ranks each transforms its layers along the other axes, and the writing
  // rank the whole along the slabs' axis only.
  std::vector<double> spectrum(const ObservedPart& part, const CellGridShape<D>& mine,
                               const std::vector<double>& counts) const {
    if (part.whole()) return power_spectrum<D>(grid_, counts);
    std::vector<std::complex<double>> field(counts.begin(), counts.end());
    for (int a = 0; a < D; ++a)
      if (a != part.axis()) transform_axis<D>(mine, field, a);
    std::vector<double> parts(2 * field.size());
    for (std::size_t c = 0; c < field.size(); ++c) {
      parts[2 * c] = field[c].real();
      parts[2 * c + 1] = field[c].imag();
    }
    parts = part.whole_field(std::move(parts), std::vector<std::int32_t>(grid_.cells.begin(), grid_.cells.end()), 2);
    if (!part.writes()) return {};
    field.resize(parts.size() / 2);
    for (std::size_t c = 0; c < field.size(); ++c) field[c] = {parts[2 * c], parts[2 * c + 1]};
    transform_axis<D>(grid_, field, part.axis());
    return power_of(field);
  }

  CellGridShape<D> grid_;
  double cut_;
};

}  // namespace granflow::srd
