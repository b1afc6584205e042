#pragma once
// Counter-based random numbers (Philox4x32-10). A draw is a pure function of
// (stream id, seed, step, item, counter): no generator state is shared, so
// results do not depend on how work is split over threads or devices.

#include <Random123/philox.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "engine/core/host_device.hpp"

namespace granflow {

class Philox {
 public:
  GRANFLOW_HD Philox(std::uint32_t stream, std::uint64_t seed, std::uint64_t step, std::uint64_t item) {
    key_ = {{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}};
    counter_ = {{static_cast<std::uint32_t>(item), static_cast<std::uint32_t>(item >> 32),
                 static_cast<std::uint32_t>(step), stream << 16}};
  }

  // Four fresh 32-bit words per call; at most 65536 calls per (stream, step, item).
  GRANFLOW_HD std::array<std::uint32_t, 4> next_words() {
    r123::Philox4x32 generator;
    const auto out = generator(counter_, key_);
    counter_.v[3] += 1;
    return {out.v[0], out.v[1], out.v[2], out.v[3]};
  }

  // Uniform in (0, 1): never 0, so logarithms are safe.
  GRANFLOW_HD double uniform() {
    if (cached_ == 0) refill();
    const std::uint64_t hi = words_[--cached_];
    const std::uint64_t lo = words_[--cached_];
    const std::uint64_t bits53 = ((hi << 32) | lo) >> 11;
    return (static_cast<double>(bits53) + 0.5) * 0x1.0p-53;
  }

  GRANFLOW_HD double normal() {
    if (has_spare_normal_) {
      has_spare_normal_ = false;
      return spare_normal_;
    }
    const double radius = std::sqrt(-2.0 * std::log(uniform()));
    const double angle = 2.0 * std::numbers::pi * uniform();
    spare_normal_ = radius * std::sin(angle);
    has_spare_normal_ = true;
    return radius * std::cos(angle);
  }

 private:
  GRANFLOW_HD void refill() {
    words_ = next_words();
    cached_ = 4;
  }

  r123::Philox4x32::key_type key_;
  r123::Philox4x32::ctr_type counter_;
  std::array<std::uint32_t, 4> words_{};
  int cached_ = 0;
  double spare_normal_ = 0.0;
  bool has_spare_normal_ = false;
};

// A seed derived from `base` for member `index` of a family (a repeat, a
// run): 64 well-mixed bits, distinct for distinct (stream, base, index).
inline std::uint64_t derived_seed(std::uint32_t stream, std::uint64_t base, std::uint64_t index) {
  const auto words = Philox(stream, base, 0, index).next_words();
  return (static_cast<std::uint64_t>(words[0]) << 32) | words[1];
}

}  // namespace granflow
