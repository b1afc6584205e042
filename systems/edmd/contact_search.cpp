#include "systems/edmd/contact_search.hpp"

#include <algorithm>
#include <cmath>

#include "systems/edmd/collision_rule.hpp"

namespace granflow::edmd {

namespace {

// contact_time() of collision_rule.hpp for every candidate, with its three
// early returns turned into selections (the same values), so that the loop
// has no branch; lanes whose value is discarded may divide by zero.
template <int D, bool shifted>
void contact_times(const double* records, const std::uint32_t* candidates, const std::uint8_t* slots,
                   const double* shifts, std::size_t count, const MotionRecord<D>& self, double now, double* times) {
  using Record = MotionRecord<D>;
  double xi[D], vi[D];
  for (int a = 0; a < D; ++a) {
    xi[a] = self.x[a];
    vi[a] = self.v[a];
  }
  const double ri = self.r;
#pragma omp simd
  for (std::size_t c = 0; c < count; ++c) {
    const std::size_t k = Record::stride * candidates[c];
    const double age = now - records[k + Record::time_offset];
    double b = 0.0, distance2 = 0.0, speed2 = 0.0;
    for (int a = 0; a < D; ++a) {
      const double v = records[k + Record::velocity_offset + a];
      double dx = records[k + a] + v * age;
      if constexpr (shifted) dx += shifts[D * slots[c] + a];
      dx -= xi[a];
      const double dv = v - vi[a];
      b += dx * dv;
      distance2 += dx * dx;
      speed2 += dv * dv;
    }
    const double sigma = ri + records[k + Record::radius_offset];
    const double gap = distance2 - sigma * sigma;
    const double discriminant = b * b - speed2 * gap;
    const double root = gap / (std::sqrt(std::max(discriminant, 0.0)) - b);
    double t = discriminant > 0.0 ? now + root : never;
    t = gap <= 0.0 ? now : t;
    times[c] = b < 0.0 ? t : never;
  }
}

}  // namespace

template <int D>
EarliestContact earliest_contact(const MotionRecord<D>* records, const std::uint32_t* candidates,
                                 const std::uint8_t* slots, const Vec<D>* shifts, std::size_t count,
                                 const MotionRecord<D>& self, double now, double* times) {
  const auto* flat = reinterpret_cast<const double*>(records);
  if (shifts)
    contact_times<D, true>(flat, candidates, slots, reinterpret_cast<const double*>(shifts), count, self, now, times);
  else
    contact_times<D, false>(flat, candidates, nullptr, nullptr, count, self, now, times);
  EarliestContact best{never, 0};
  for (std::size_t c = 0; c < count; ++c)
    if (times[c] < best.time) best = {times[c], c};
  return best;
}

template EarliestContact earliest_contact<2>(const MotionRecord<2>*, const std::uint32_t*, const std::uint8_t*,
                                             const Vec<2>*, std::size_t, const MotionRecord<2>&, double, double*);
template EarliestContact earliest_contact<3>(const MotionRecord<3>*, const std::uint32_t*, const std::uint8_t*,
                                             const Vec<3>*, std::size_t, const MotionRecord<3>&, double, double*);

}  // namespace granflow::edmd
