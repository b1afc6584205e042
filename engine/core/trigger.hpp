#pragma once
// When an observer runs: at listed times (log-spaced or evenly spaced output
// times), every Δt, at listed steps or every N steps (for event-driven runs
// the step is the pair-collision count), at the end, or whenever any of
// several triggers fires. The Runner advances the simulation to the earliest
// time or step any trigger asks for, then runs the observers whose trigger
// is due. A trigger remembers how far it has come; a resumed run restores
// that by passing every trigger to the time and step of the last round, so
// a resumed run may change output times or the stop time.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace granflow {

class Trigger {
 public:
  static constexpr double never = std::numeric_limits<double>::infinity();
  static constexpr std::int64_t no_step = std::numeric_limits<std::int64_t>::max();

  virtual ~Trigger() = default;
  // The next time / step at which it fires (never / no_step: none).
  virtual double next_time() const { return never; }
  virtual std::int64_t next_step() const { return no_step; }
  // Moves past every firing at or before (time, step).
  virtual void pass(double time, std::int64_t step) = 0;
  // Fires once more when the run ends.
  virtual bool at_end() const { return false; }
  // Whether its firing due at (time, step) is one of its own, which a
  // longer run has as well, rather than one set by where the run stops:
  // the last time of an output list (lists are built to end at the stop)
  // or an end cap.
  virtual bool own_firing(double, std::int64_t) const { return false; }
  // Whether a firing is due at (time, step).
  bool due(double time, std::int64_t step) const;
};

using TriggerPtr = std::shared_ptr<Trigger>;

// Relative tolerance within which two trigger times count as one.
inline constexpr double trigger_time_tolerance = 1e-12;

inline bool time_reached(double due, double now) {
  return due <= now || due <= now + trigger_time_tolerance * std::abs(now);
}

inline bool Trigger::due(double time, std::int64_t step) const {
  return time_reached(next_time(), time) || next_step() <= step;
}

// At each of a sorted list of times.
class AtTimes : public Trigger {
 public:
  explicit AtTimes(std::vector<double> times) : times_(std::move(times)) {}
  double next_time() const override { return next_ < times_.size() ? times_[next_] : never; }
  void pass(double time, std::int64_t) override {
    while (next_ < times_.size() && time_reached(times_[next_], time)) ++next_;
  }
  const std::vector<double>& times() const { return times_; }

 private:
  std::vector<double> times_;
  std::size_t next_ = 0;
};

// At t = k * interval for k = first, first + 1, ..., capped at `end` (which fires last).
class EveryTime : public Trigger {
 public:
  EveryTime(double interval, double end, std::uint64_t first = 0) : interval_(interval), end_(end), k_(first) {}
  double next_time() const override {
    if (done_) return never;
    return std::min(end_, static_cast<double>(k_) * interval_);
  }
  bool own_firing(double time, std::int64_t) const override {
    return !done_ && time_reached(static_cast<double>(k_) * interval_, time);
  }
  void pass(double time, std::int64_t) override {
    // Far behind (a resumed run, an interval far below the step): jump to
    // one firing before `time` instead of counting there one by one.
    const double behind = std::floor(time / interval_) - 1.0;
    if (!done_ && behind > static_cast<double>(k_)) {
      if (!(behind < 9e18)) {
        done_ = true;  // more firings than a counter holds: none can be told apart
        return;
      }
      k_ = static_cast<std::uint64_t>(behind);
    }
    while (!done_ && time_reached(next_time(), time)) {
      if (next_time() >= end_) done_ = true;
      ++k_;
    }
  }

 private:
  double interval_;
  double end_;
  std::uint64_t k_;
  bool done_ = false;
};

// At each of a sorted list of steps.
class AtSteps : public Trigger {
 public:
  explicit AtSteps(std::vector<std::int64_t> steps) : steps_(std::move(steps)) {}
  std::int64_t next_step() const override { return next_ < steps_.size() ? steps_[next_] : no_step; }
  void pass(double, std::int64_t step) override {
    while (next_ < steps_.size() && steps_[next_] <= step) ++next_;
  }

 private:
  std::vector<std::int64_t> steps_;
  std::size_t next_ = 0;
};

// At steps 0, n, 2n, ...
class EverySteps : public Trigger {
 public:
  // Steps first, first + n, first + 2n, ...
  explicit EverySteps(std::int64_t n, std::int64_t first = 0) : n_(n), next_(first) {}
  std::int64_t next_step() const override { return next_; }
  void pass(double, std::int64_t step) override {
    while (next_ <= step) next_ += n_;
  }
  bool own_firing(double, std::int64_t) const override { return true; }

 private:
  std::int64_t n_;
  std::int64_t next_ = 0;
};

// Once, when the run ends (finished, stopped or failed).
class AtEnd : public Trigger {
 public:
  void pass(double, std::int64_t) override {}
  bool at_end() const override { return true; }
};

// Whenever any of its parts fires.
class AnyOf : public Trigger {
 public:
  explicit AnyOf(std::vector<TriggerPtr> parts) : parts_(std::move(parts)) {}
  double next_time() const override {
    double t = never;
    for (const auto& p : parts_) t = std::min(t, p->next_time());
    return t;
  }
  std::int64_t next_step() const override {
    std::int64_t s = no_step;
    for (const auto& p : parts_) s = std::min(s, p->next_step());
    return s;
  }
  // Parts shared with other observers are passed by the Runner itself; passing twice is harmless.
  void pass(double time, std::int64_t step) override {
    for (auto& p : parts_) p->pass(time, step);
  }
  bool at_end() const override {
    return std::any_of(parts_.begin(), parts_.end(), [](const auto& p) { return p->at_end(); });
  }
  bool own_firing(double time, std::int64_t step) const override {
    return std::any_of(parts_.begin(), parts_.end(), [&](const auto& p) {
      return p->due(time, step) && p->own_firing(time, step);
    });
  }
  const std::vector<TriggerPtr>& parts() const { return parts_; }

 private:
  std::vector<TriggerPtr> parts_;
};

}  // namespace granflow
