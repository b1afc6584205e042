#pragma once
// Progress of a long run: fraction done, a rate (e.g. collisions/s) and the
// estimated time left. On a terminal it redraws one line; otherwise it prints
// a plain line every few seconds, which reads well in a log file.

#include <chrono>
#include <cstdio>
#include <string>

namespace granflow {

class Progress {
 public:
  Progress(std::string label, std::string rate_unit, bool enabled = true);
  // fraction in [0, 1]; work = cumulative count the rate is measured on.
  // detail: shown after the percentage (e.g. "12/30 runs"); may be empty.
  void update(double fraction, double work, const std::string& detail = "");
  void finish();

 private:
  std::string label_;
  std::string rate_unit_;
  bool enabled_;
  bool terminal_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
  double interval_seconds_;
  bool printed_ = false;
};

}  // namespace granflow
