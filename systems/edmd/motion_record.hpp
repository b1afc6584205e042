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

  // Left unset, so that sizing an array of records touches none of its
  // memory: the pages become resident only as the records are written.
  MotionRecord() {}  // NOLINT(modernize-use-equals-default): "= default" would zero them
  MotionRecord(const Vec<D>& position, const Vec<D>& velocity, double time, double radius)
      : x(position), v(velocity), t(time), r(radius) {}

  // Field offsets in doubles, for kernels that read records as flat arrays.
  static constexpr int velocity_offset = D;
  static constexpr int time_offset = 2 * D;
  static constexpr int radius_offset = 2 * D + 1;
  static constexpr std::size_t stride = sizeof(MotionRecord) / sizeof(double);
};

static_assert(sizeof(MotionRecord<3>) == 64 && sizeof(MotionRecord<2>) == 48);

}  // namespace granflow::edmd
