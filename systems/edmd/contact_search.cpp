#include "systems/edmd/contact_search.hpp"

#include <algorithm>
#include <cmath>

#include "systems/edmd/collision_rule.hpp"

namespace granflow::edmd {

template <int D>
EarliestContact earliest_contact(CandidateBuffer<D>& candidates, std::size_t begin, std::size_t end,
                                 const MotionRecord<D>& self, double now) {
  using Buffer = CandidateBuffer<D>;
  constexpr std::size_t block = Buffer::block;
  if (begin >= end) return {never, begin};
  double xi[D], vi[D];
  for (int a = 0; a < D; ++a) {
    xi[a] = self.x[a];
    vi[a] = self.v[a];
  }
  const double ri = self.r;
  double* times = candidates.times();
  // contact_time() of collision_rule.hpp with its three early returns turned
  // into selections (the same values), so that the loop has no branch; lanes
  // whose value is discarded may divide by zero. The test covers the whole
  // blocks that hold the range; what lies outside it is either another
  // candidate of the buffer or an entry that Writer::close() made fail.
  const std::size_t first_block = begin / block;
  const std::size_t end_block = (end + block - 1) / block;
  double earliest = never;
  for (std::size_t k = first_block; k < end_block; ++k) {
    const double* entry = candidates.data() + k * Buffer::rows * block;
    double* time = times + k * block;
#pragma omp simd reduction(min : earliest)
    for (std::size_t lane = 0; lane < block; ++lane) {
      double b = 0.0, distance2 = 0.0, speed2 = 0.0;
      for (int a = 0; a < D; ++a) {
        const double dx = entry[static_cast<std::size_t>(a) * block + lane] - xi[a];
        const double dv = entry[static_cast<std::size_t>(D + a) * block + lane] - vi[a];
        b += dx * dv;
        distance2 += dx * dx;
        speed2 += dv * dv;
      }
      const double sigma = ri + entry[Buffer::radius_row * block + lane];
      const double gap = distance2 - sigma * sigma;
      const double discriminant = b * b - speed2 * gap;
      const double root = gap / (std::sqrt(std::max(discriminant, 0.0)) - b);
      double t = discriminant > 0.0 ? now + root : never;
      t = gap <= 0.0 ? now : t;
      t = b < 0.0 ? t : never;
      time[lane] = t;
      earliest = std::min(earliest, t);
    }
  }
  if (earliest == never) return {never, begin};
  std::size_t first = first_block * block;
  while (times[first] != earliest) ++first;
  return {earliest, first};
}

template EarliestContact earliest_contact<2>(CandidateBuffer<2>&, std::size_t, std::size_t, const MotionRecord<2>&,
                                             double);
template EarliestContact earliest_contact<3>(CandidateBuffer<3>&, std::size_t, std::size_t, const MotionRecord<3>&,
                                             double);

}  // namespace granflow::edmd
