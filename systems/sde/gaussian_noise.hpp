#pragma once
// Gaussian noise for SDE stepping, written so that a loop over particles
// vectorises: Philox4x32-10 on plain 32-bit words (the same numbers as
// Random123's philox4x32 for the counter and key of engine/core/rng.hpp's
// Philox), and the Box-Muller transform in single precision (the noise of a
// step needs no more). Uniforms take the top 24 bits of a word, exact in a
// float; the radius then reaches 5.9 sigma at most, an event of probability
// 4e-9 per draw.

#include <cmath>
#include <cstdint>
#include <numbers>

#include "engine/core/host_device.hpp"

namespace granflow::sde {

GRANFLOW_HD inline void philox4x32_10(std::uint32_t& c0, std::uint32_t& c1, std::uint32_t& c2, std::uint32_t& c3,
                                      std::uint32_t k0, std::uint32_t k1) {
  for (int round = 0; round < 10; ++round) {
    if (round > 0) {
      k0 += 0x9E3779B9u;
      k1 += 0xBB67AE85u;
    }
    const std::uint64_t p0 = static_cast<std::uint64_t>(0xD2511F53u) * c0;
    const std::uint64_t p1 = static_cast<std::uint64_t>(0xCD9E8D57u) * c2;
    const auto hi0 = static_cast<std::uint32_t>(p0 >> 32), lo0 = static_cast<std::uint32_t>(p0);
    const auto hi1 = static_cast<std::uint32_t>(p1 >> 32), lo1 = static_cast<std::uint32_t>(p1);
    c0 = hi1 ^ c1 ^ k0;
    c1 = lo1;
    c2 = hi0 ^ c3 ^ k1;
    c3 = lo0;
  }
}

// Box-Muller: N(0, 1) pairs radius * (cos, sin)(angle) from two uniform
// 32-bit words. The top 24 bits go through int32, which converts to float in
// one vector instruction.
GRANFLOW_HD inline float box_muller_radius(std::uint32_t word) {
  const float u = (static_cast<float>(static_cast<std::int32_t>(word >> 8)) + 0.5f) * 0x1.0p-24f;  // in (0, 1)
  return std::sqrt(-2.0f * std::log(u));
}
GRANFLOW_HD inline float box_muller_angle(std::uint32_t word) {
  return 2.0f * std::numbers::pi_v<float> * (static_cast<float>(static_cast<std::int32_t>(word >> 8)) * 0x1.0p-24f);
}

}  // namespace granflow::sde
