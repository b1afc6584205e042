#pragma once
// The Maxwell-Boltzmann speed distribution in 2D and 3D (k_B = 1) and a
// chi-square goodness-of-fit test of sampled speeds against it, with bins of
// equal expected probability.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace granflow::theory {

// Probability density of the speed v for particles of mass m at temperature T.
template <int D>
double speed_density(double v, double temperature, double mass) {
  const double a = mass / temperature;
  if constexpr (D == 2)
    return a * v * std::exp(-0.5 * a * v * v);
  else
    return std::sqrt(2.0 / std::numbers::pi) * std::pow(a, 1.5) * v * v * std::exp(-0.5 * a * v * v);
}

// Cumulative distribution of the speed in units of sqrt(T/m).
template <int D>
double speed_cdf(double x) {
  if constexpr (D == 2)
    return 1.0 - std::exp(-0.5 * x * x);
  else
    return std::erf(x / std::numbers::sqrt2) - std::sqrt(2.0 / std::numbers::pi) * x * std::exp(-0.5 * x * x);
}

template <int D>
double mean_speed(double temperature, double mass) {
  return D == 3 ? std::sqrt(8.0 * temperature / (std::numbers::pi * mass))
                : std::sqrt(std::numbers::pi * temperature / (2.0 * mass));
}
template <int D>
double rms_speed(double temperature, double mass) { return std::sqrt(D * temperature / mass); }
template <int D>
double most_probable_speed(double temperature, double mass) { return std::sqrt((D - 1) * temperature / mass); }

// Bin edges (in units of sqrt(T/m)) with equal Maxwell-Boltzmann probability.
template <int D>
std::vector<double> equal_probability_edges(int bins) {
  std::vector<double> edges{0.0};
  for (int k = 1; k < bins; ++k) {
    const double target = static_cast<double>(k) / bins;
    double lo = 0.0, hi = 10.0;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (speed_cdf<D>(mid) < target ? lo : hi) = mid;
    }
    edges.push_back(0.5 * (lo + hi));
  }
  edges.push_back(std::numeric_limits<double>::infinity());
  return edges;
}

// Upper 0.999 quantile of the chi-square distribution with k degrees of
// freedom (Wilson-Hilferty; better than 0.5 % for k >= 10).
inline double chi_square_critical_0999(int k) {
  const double z = 3.090232;  // standard normal 0.999 quantile
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3);
}

// Pearson's chi-square of speeds against Maxwell-Boltzmann at (T, m).
template <int D>
double speed_chi_square(const std::vector<double>& speeds, double temperature, double mass, int bins) {
  const auto edges = equal_probability_edges<D>(bins);
  std::vector<double> observed(static_cast<std::size_t>(bins), 0.0);
  const double unit = std::sqrt(temperature / mass);
  for (double v : speeds) {
    const auto k = std::upper_bound(edges.begin(), edges.end(), v / unit) - edges.begin() - 1;
    observed[static_cast<std::size_t>(k)] += 1.0;
  }
  const double expected = static_cast<double>(speeds.size()) / bins;
  double chi2 = 0.0;
  for (double o : observed) chi2 += (o - expected) * (o - expected) / expected;
  return chi2;
}

}  // namespace granflow::theory
