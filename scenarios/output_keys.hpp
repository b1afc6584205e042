#pragma once
// The output-time keys of scenarios that write time series at log-spaced or
// evenly spaced times, and the trigger they describe.

#include <limits>
#include <memory>

#include "engine/core/config.hpp"
#include "engine/core/output_times.hpp"
#include "engine/core/trigger.hpp"

namespace granflow::scenarios {

inline void declare_output_time_keys(ConfigSchema& s, double first, std::int64_t points_per_decade) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  s.choice("output.spacing", "log", {"log", "linear"}, "log-spaced or evenly spaced output times")
      .real("output.interval", 1.0, 0.0, inf, "time between outputs (linear spacing)", true)
      .real("output.first", first, 0.0, inf, "first output time after t = 0 (log spacing)", true)
      .integer("output.points_per_decade", points_per_decade, 1, 1000, "outputs per decade of time (log spacing)");
}

// t = 0, then the configured times up to run.t_stop (included).
inline std::shared_ptr<AtTimes> output_times_from(const Config& c) {
  const double t_stop = c.real("run.t_stop");
  return std::make_shared<AtTimes>(
      c.text("output.spacing") == "log"
          ? log_output_times(t_stop, c.real("output.first"), static_cast<int>(c.integer("output.points_per_decade")))
          : linear_output_times(t_stop, c.real("output.interval")));
}

}  // namespace granflow::scenarios
