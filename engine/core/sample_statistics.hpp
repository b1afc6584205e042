#pragma once
// Mean and standard error of the mean of independent samples (runs,
// repeats): sqrt(sum (x - mean)^2 / (n - 1) / n); nan where undefined.

#include <cmath>
#include <vector>

namespace granflow {

struct MeanAndError {
  double mean;
  double standard_error;
};

inline MeanAndError mean_and_standard_error(const std::vector<double>& samples) {
  const auto n = static_cast<double>(samples.size());
  if (samples.empty()) return {std::nan(""), std::nan("")};
  double sum = 0.0;
  for (double x : samples) sum += x;
  const double mean = sum / n;
  double squares = 0.0;
  for (double x : samples) squares += (x - mean) * (x - mean);
  return {mean, samples.size() > 1 ? std::sqrt(squares / (n - 1) / n) : std::nan("")};
}

}  // namespace granflow
