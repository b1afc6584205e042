#pragma once
// Output times of a run: t = 0, then evenly spaced or log-spaced up to t_stop
// (which is always included).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/core/config.hpp"

namespace granflow {

// More output times than this is a configuration mistake, not a request.
inline constexpr double max_output_times = 1e7;

// `key` names the interval's key in the message.
inline void check_output_count(double t_stop, double interval, const std::string& key = "output.interval") {
  if (t_stop / interval > max_output_times)
    throw ConfigError(fmt::format("{} = {} with run.t_stop = {} asks for {:.3g} output times (at most {:g}); "
                                  "increase {}",
                                  key, interval, t_stop, t_stop / interval, max_output_times, key));
}

inline std::vector<double> linear_output_times(double t_stop, double interval) {
  check_output_count(t_stop, interval);
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
  const double count = std::max(0.0, std::log10(t_stop / first)) * points_per_decade;
  if (count > max_output_times)
    throw ConfigError(fmt::format("output.first = {} and output.points_per_decade = {} up to run.t_stop = {} ask "
                                  "for {:.3g} output times (at most {:g})",
                                  first, points_per_decade, t_stop, count, max_output_times));
  std::vector<double> times{0.0};
  for (std::size_t k = 0;; ++k) {
    const double t = first * std::pow(10.0, static_cast<double>(k) / points_per_decade);
    if (t >= t_stop * (1 - 1e-12)) break;
    times.push_back(t);
  }
  times.push_back(t_stop);
  return times;
}

// The log-spaced times above as whole steps of `dt`: step 0, then each
// time's nearest step where it is later than the previous one, up to the
// step of t_stop (included).
inline std::vector<std::int64_t> log_output_steps(double t_stop, double first, int points_per_decade, double dt) {
  const auto last = static_cast<std::int64_t>(std::llround(t_stop / dt));
  std::vector<std::int64_t> steps;
  for (double t : log_output_times(t_stop, first, points_per_decade)) {
    const auto step = std::min<std::int64_t>(last, std::llround(t / dt));
    if (steps.empty() || step > steps.back()) steps.push_back(step);
  }
  return steps;
}

}  // namespace granflow
