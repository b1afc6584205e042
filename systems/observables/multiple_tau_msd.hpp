#pragma once
// Time-averaged MSD (Metzler et al. 2014) accumulated on the fly with a
// multiple-tau scheme (Ramirez et al. 2010), so memory grows with the logarithm of the run length,
// not with it: level 0 keeps the last `points` samples and measures lags 1 ..
// points-1; every `factor`-th sample of a level is passed on to the next,
// which measures lags points/factor .. points-1 in its own (factor times
// coarser) units. Samples are decimated, not block-averaged, so every lag is
// measured without bias; long lags simply have fewer time origins.
//
// Per particle it keeps the sum of squared displacements at every lag, so
// besides the particle-averaged time-averaged MSD it gives the ergodicity-
// breaking parameter EB = <(delta^2)^2> / <delta^2>^2 - 1 over particles
// (0 for an ergodic process in the long-measurement limit).

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "engine/core/state_map.hpp"

namespace granflow {

class MultipleTauMsd {
 public:
  // `coordinates` numbers per particle (the dimension); lags up to `max_lag` samples.
  MultipleTauMsd(std::size_t particles, int coordinates, std::uint64_t max_lag, int points = 16, int factor = 2)
      : particles_(particles), coordinates_(coordinates), points_(points), factor_(factor) {
    std::uint64_t reach = static_cast<std::uint64_t>(points - 1);
    levels_ = 1;
    while (reach < max_lag) {
      reach *= static_cast<std::uint64_t>(factor);
      ++levels_;
    }
    history_.assign(static_cast<std::size_t>(levels_) * points_ * particles_ * coordinates_, 0.0);
    seen_.assign(static_cast<std::size_t>(levels_), 0);
    sums_.assign(static_cast<std::size_t>(levels_) * points_ * particles_, 0.0);
    origins_.assign(static_cast<std::size_t>(levels_) * points_, 0);
  }

  // One sample: `positions` holds particles x coordinates unwrapped values.
  void add(const double* positions) { add_to_level(0, positions); }

  struct Result {
    std::vector<double> lag;           // in samples
    std::vector<double> msd;           // particle average of the time-averaged MSD
    std::vector<double> ergodicity_breaking;
  };
  Result result() const {
    Result r;
    for (int level = 0; level < levels_; ++level) {
      const std::uint64_t unit = power(level);
      for (int j = level == 0 ? 1 : points_ / factor_; j < points_; ++j) {
        const std::size_t slot = static_cast<std::size_t>(level) * points_ + j;
        if (origins_[slot] == 0) continue;
        double mean = 0.0, square = 0.0;
        for (std::size_t p = 0; p < particles_; ++p) {
          const double d = sums_[slot * particles_ + p] / static_cast<double>(origins_[slot]);
          mean += d;
          square += d * d;
        }
        mean /= static_cast<double>(particles_);
        square /= static_cast<double>(particles_);
        r.lag.push_back(static_cast<double>(unit * static_cast<std::uint64_t>(j)));
        r.msd.push_back(mean);
        r.ergodicity_breaking.push_back(mean > 0 ? square / (mean * mean) - 1.0 : 0.0);
      }
    }
    return r;
  }

  // Everything it has accumulated, for checkpoints.
  StateMap save_state() const {
    return {{"history", history_},
            {"seen", {seen_.begin(), seen_.end()}},
            {"sums", sums_},
            {"origins", {origins_.begin(), origins_.end()}}};
  }
  void restore_state(const StateMap& state) {
    const auto& history = state.at("history");
    const auto& seen = state.at("seen");
    const auto& sums = state.at("sums");
    const auto& origins = state.at("origins");
    if (history.size() != history_.size() || seen.size() != seen_.size() || sums.size() != sums_.size() ||
        origins.size() != origins_.size())
      throw std::invalid_argument("checkpoint correlator does not match its configuration");
    history_ = history;
    sums_ = sums;
    for (std::size_t k = 0; k < seen.size(); ++k) seen_[k] = static_cast<std::uint64_t>(seen[k]);
    for (std::size_t k = 0; k < origins.size(); ++k) origins_[k] = static_cast<std::uint64_t>(origins[k]);
  }

  std::size_t bytes() const {
    return (history_.size() + sums_.size()) * sizeof(double) + origins_.size() * sizeof(std::uint64_t);
  }

 private:
  std::uint64_t power(int level) const {
    std::uint64_t u = 1;
    for (int l = 0; l < level; ++l) u *= static_cast<std::uint64_t>(factor_);
    return u;
  }
  double* sample(int level, std::uint64_t index) {
    const std::size_t ring = static_cast<std::size_t>(index % static_cast<std::uint64_t>(points_));
    return &history_[((static_cast<std::size_t>(level) * points_ + ring) * particles_) * coordinates_];
  }

  void add_to_level(int level, const double* positions) {
    if (level >= levels_) return;
    const std::uint64_t index = seen_[static_cast<std::size_t>(level)]++;
    double* slot_now = sample(level, index);
    for (std::size_t k = 0; k < particles_ * coordinates_; ++k) slot_now[k] = positions[k];
    const std::uint64_t available = std::min<std::uint64_t>(index, static_cast<std::uint64_t>(points_ - 1));
    for (int j = level == 0 ? 1 : points_ / factor_; j <= static_cast<int>(available); ++j) {
      const double* then = sample(level, index - static_cast<std::uint64_t>(j));
      const std::size_t slot = static_cast<std::size_t>(level) * points_ + j;
      ++origins_[slot];
      double* sums = &sums_[slot * particles_];
      for (std::size_t p = 0; p < particles_; ++p) {
        double d2 = 0.0;
        for (int a = 0; a < coordinates_; ++a) {
          const double d = slot_now[p * coordinates_ + a] - then[p * coordinates_ + a];
          d2 += d * d;
        }
        sums[p] += d2;
      }
    }
    if ((index + 1) % static_cast<std::uint64_t>(factor_) == 0) add_to_level(level + 1, slot_now);
  }

  std::size_t particles_;
  int coordinates_;
  int points_;
  int factor_;
  int levels_ = 1;
  std::vector<double> history_;
  std::vector<std::uint64_t> seen_;
  std::vector<double> sums_;
  std::vector<std::uint64_t> origins_;
};

}  // namespace granflow
