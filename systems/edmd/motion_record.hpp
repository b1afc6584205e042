#pragma once
// What a prediction reads of a neighbour, packed so that one neighbour is one
// 64-byte cache line in 3D: its position at its own local time (delayed
// states, Marin, Risso & Cordero 1993), its velocity, that time and its radius.

#include "components/vector.hpp"

namespace granflow::edmd {

template <int D>
struct alignas(D == 3 ? 64 : 16) MotionRecord {
  Vec<D> x;  // position at local time t, wrapped into the box
  Vec<D> v;
  double t;
  double r;

  // Field offsets in doubles, for kernels that read records as flat arrays.
  static constexpr int velocity_offset = D;
  static constexpr int time_offset = 2 * D;
  static constexpr int radius_offset = 2 * D + 1;
  static constexpr std::size_t stride = sizeof(MotionRecord) / sizeof(double);
};

static_assert(sizeof(MotionRecord<3>) == 64 && sizeof(MotionRecord<2>) == 48);

}  // namespace granflow::edmd
