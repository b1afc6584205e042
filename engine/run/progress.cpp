#include "engine/run/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>

namespace granflow {

namespace {
std::string duration_text(double seconds) {
  if (!(seconds >= 0) || seconds > 1e7) return "?";
  const auto s = static_cast<long>(seconds + 0.5);
  if (s >= 3600) return fmt::format("{}h{:02}m", s / 3600, (s % 3600) / 60);
  if (s >= 60) return fmt::format("{}m{:02}s", s / 60, s % 60);
  return fmt::format("{}s", s);
}
}  // namespace

Progress::Progress(std::string label, std::string rate_unit, bool enabled)
    : label_(std::move(label)),
      rate_unit_(std::move(rate_unit)),
      enabled_(enabled),
      terminal_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_),
      interval_seconds_(terminal_ ? 0.25 : 5.0) {}

void Progress::update(double fraction, double work, const std::string& detail) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_print_).count() < interval_seconds_) return;
  last_print_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  fraction = std::clamp(fraction, 0.0, 1.0);
  const double rate = elapsed > 0 ? work / elapsed : 0.0;
  const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : -1.0;
  const std::string rate_text = rate_unit_.empty() ? "" : fmt::format(" | {:.3g} {}", rate, rate_unit_);
  const std::string line = fmt::format("{}: {:5.1f}%{}{} | elapsed {} | ETA {}", label_, 100.0 * fraction,
                                       detail.empty() ? "" : " (" + detail + ")", rate_text, duration_text(elapsed),
                                       duration_text(eta));
  if (terminal_)
    fmt::print(stderr, "\r{:<90}", line);
  else
    fmt::print(stderr, "{}\n", line);
  std::fflush(stderr);
  printed_ = true;
}

void Progress::finish() {
  if (enabled_ && terminal_ && printed_) fmt::print(stderr, "\n");
}

}  // namespace granflow
