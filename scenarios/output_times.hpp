#pragma once
// Output times of a run: t = 0, then evenly spaced or log-spaced up to t_stop
// (which is always included).

#include <cmath>
#include <stdexcept>
#include <vector>

namespace granflow {

inline std::vector<double> linear_output_times(double t_stop, double interval) {
  std::vector<double> times{0.0};
  for (std::size_t k = 1;; ++k) {
    const double t = static_cast<double>(k) * interval;
    if (t >= t_stop * (1 - 1e-12)) break;
    times.push_back(t);
  }
  times.push_back(t_stop);
  return times;
}

inline std::vector<double> log_output_times(double t_stop, double first, int points_per_decade) {
  std::vector<double> times{0.0};
  for (std::size_t k = 0;; ++k) {
    const double t = first * std::pow(10.0, static_cast<double>(k) / points_per_decade);
    if (t >= t_stop * (1 - 1e-12)) break;
    times.push_back(t);
  }
  times.push_back(t_stop);
  return times;
}

}  // namespace granflow
