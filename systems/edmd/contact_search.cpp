#include "systems/edmd/contact_search.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "systems/edmd/collision_rule.hpp"

namespace granflow::edmd {

namespace {

// contact_time() of collision_rule.hpp with its three early returns turned
// into selections (the same values), so that the test has no branch; lanes
// whose value is discarded may divide by zero or take the root of a negative
// discriminant. Sums start from their first term, not from zero (which would
// only turn a -0 into +0, and b = -0 is rejected either way). A candidate's
// position is moved to `now` and shifted to its image by the same operations
// in the same order in both versions (x + v (now - t), then the shift), and
// without contracted multiply-adds, so the times are bit for bit the same
// whatever the instruction set.
#if !defined(__AVX2__)
template <int D>
double scalar_contact(const MotionRecord<D>& record, const double* shift, const double* xi, const double* vi,
                      double ri, double now) {
  const double age = now - record.t;
  double b, distance2, speed2;
  for (int a = 0; a < D; ++a) {
    const double v = record.v[a];
    double x = record.x[a] + v * age;
    x += shift[a];
    const double dx = x - xi[a];
    const double dv = v - vi[a];
    b = a == 0 ? dx * dv : b + dx * dv;
    distance2 = a == 0 ? dx * dx : distance2 + dx * dx;
    speed2 = a == 0 ? dv * dv : speed2 + dv * dv;
  }
  const double sigma = ri + record.r;
  const double gap = distance2 - sigma * sigma;
  const double discriminant = b * b - speed2 * gap;
  const double root = gap / (std::sqrt(discriminant) - b);
  double t = discriminant > 0.0 ? now + root : never;
  t = gap <= 0.0 ? now : t;
  t = b < 0.0 ? t : never;
  return t;
}
#else
// Four candidates' fields, one vector per field, the lanes in list order.
template <int D>
struct Fields {
  __m256d x[D], v[D], t, r;
};

// Records are read as whole aligned rows and transposed in registers where a
// record is one 64-byte line (3D): two loads per record and shuffles cost
// less time than gathers of each field. In 2D they are gathered.
template <int D>
[[gnu::always_inline]] inline Fields<D> load_fields(const double* records, const std::uint32_t* offset) {
  Fields<D> f;
  if constexpr (D == 3) {
    static_assert(MotionRecord<3>::stride == 8 && MotionRecord<3>::velocity_offset == 3 &&
                  MotionRecord<3>::time_offset == 6 && MotionRecord<3>::radius_offset == 7);
    __m256d front[4], back[4];  // (x0, x1, x2, v0) and (v1, v2, t, r)
    for (int k = 0; k < 4; ++k) {
      const double* record = records + offset[k];
      front[k] = _mm256_load_pd(record);
      back[k] = _mm256_load_pd(record + 4);
    }
    const auto transpose = [](const __m256d* rows, __m256d& c0, __m256d& c1, __m256d& c2, __m256d& c3) {
      const __m256d even01 = _mm256_unpacklo_pd(rows[0], rows[1]);  // (c0, c0, c2, c2) of rows 0 and 1
      const __m256d odd01 = _mm256_unpackhi_pd(rows[0], rows[1]);
      const __m256d even23 = _mm256_unpacklo_pd(rows[2], rows[3]);
      const __m256d odd23 = _mm256_unpackhi_pd(rows[2], rows[3]);
      c0 = _mm256_permute2f128_pd(even01, even23, 0x20);
      c2 = _mm256_permute2f128_pd(even01, even23, 0x31);
      c1 = _mm256_permute2f128_pd(odd01, odd23, 0x20);
      c3 = _mm256_permute2f128_pd(odd01, odd23, 0x31);
    };
    transpose(front, f.x[0], f.x[1], f.x[2], f.v[0]);
    transpose(back, f.v[1], f.v[2], f.t, f.r);
  } else {
    const __m256i at = _mm256_cvtepu32_epi64(_mm_loadu_si128(reinterpret_cast<const __m128i*>(offset)));
    for (int a = 0; a < D; ++a) {
      f.x[a] = _mm256_i64gather_pd(records + a, at, 8);
      f.v[a] = _mm256_i64gather_pd(records + MotionRecord<D>::velocity_offset + a, at, 8);
    }
    f.t = _mm256_i64gather_pd(records + MotionRecord<D>::time_offset, at, 8);
    f.r = _mm256_i64gather_pd(records + MotionRecord<D>::radius_offset, at, 8);
  }
  return f;
}

// Four candidates at once. Where the prediction sees periodic images
// (WithShifts), a group whose candidates are all unshifted (the zero shift at
// offset `unshifted`) skips the shift, which would add exact zeros.
template <int D, bool WithShifts>
[[gnu::always_inline]] inline __m256d vector_contact(const double* records, const double* shifts,
                                                    const std::uint32_t* offset, const std::int32_t* shift_offset,
                                                    std::int32_t unshifted, const __m256d* xi, const __m256d* vi,
                                                    __m256d ri, __m256d now) {
  Fields<D> f = load_fields<D>(records, offset);
  const __m256d age = _mm256_sub_pd(now, f.t);
  bool shifted = false;
  __m256i shift_at = _mm256_setzero_si256();
  if constexpr (WithShifts) {
    const __m128i offsets = _mm_loadu_si128(reinterpret_cast<const __m128i*>(shift_offset));
    shifted = _mm_movemask_epi8(_mm_cmpeq_epi32(offsets, _mm_set1_epi32(unshifted))) != 0xffff;
    shift_at = _mm256_cvtepi32_epi64(offsets);
  }
  __m256d b, distance2, speed2;
  for (int a = 0; a < D; ++a) {
    __m256d x = _mm256_add_pd(f.x[a], _mm256_mul_pd(f.v[a], age));
    if (WithShifts && shifted) x = _mm256_add_pd(x, _mm256_i64gather_pd(shifts + a, shift_at, 8));
    const __m256d dx = _mm256_sub_pd(x, xi[a]);
    const __m256d dv = _mm256_sub_pd(f.v[a], vi[a]);
    b = a == 0 ? _mm256_mul_pd(dx, dv) : _mm256_add_pd(b, _mm256_mul_pd(dx, dv));
    distance2 = a == 0 ? _mm256_mul_pd(dx, dx) : _mm256_add_pd(distance2, _mm256_mul_pd(dx, dx));
    speed2 = a == 0 ? _mm256_mul_pd(dv, dv) : _mm256_add_pd(speed2, _mm256_mul_pd(dv, dv));
  }
  const __m256d sigma = _mm256_add_pd(ri, f.r);
  const __m256d gap = _mm256_sub_pd(distance2, _mm256_mul_pd(sigma, sigma));
  const __m256d discriminant = _mm256_sub_pd(_mm256_mul_pd(b, b), _mm256_mul_pd(speed2, gap));
  const __m256d zero = _mm256_setzero_pd();
  const __m256d root = _mm256_div_pd(gap, _mm256_sub_pd(_mm256_sqrt_pd(discriminant), b));
  const __m256d infinite = _mm256_set1_pd(never);
  // Ordered comparisons: a NaN lane (the sentinel) fails every test.
  __m256d t = _mm256_blendv_pd(infinite, _mm256_add_pd(now, root), _mm256_cmp_pd(discriminant, zero, _CMP_GT_OQ));
  t = _mm256_blendv_pd(t, now, _mm256_cmp_pd(gap, zero, _CMP_LE_OQ));
  return _mm256_blendv_pd(infinite, t, _mm256_cmp_pd(b, zero, _CMP_LT_OQ));
}
#endif

}  // namespace

template <int D>
EarliestContact earliest_contact(CandidateList& candidates, std::size_t begin, std::size_t end,
                                 const MotionRecord<D>* records, const double* shifts, std::int32_t unshifted,
                                 const MotionRecord<D>& self, double now) {
  constexpr std::size_t group = CandidateList::group;
  if (begin >= end) return {never, begin};
  double* times = candidates.times();
  const std::uint32_t* offset = candidates.record_offsets();
  const std::int32_t* shift_offset = candidates.shift_offsets();
  // The test covers the whole groups that hold the range; what lies outside
  // it is either another candidate of the list or the sentinel.
  const std::size_t first = (begin / group) * group;
  const std::size_t last = (end + group - 1) / group * group;
  double earliest = never;
#if defined(__AVX2__)
  static_assert(group == 4);
  const auto* flat = reinterpret_cast<const double*>(records);
  __m256d x[D], v[D];
  for (int a = 0; a < D; ++a) {
    x[a] = _mm256_broadcast_sd(&self.x[a]);
    v[a] = _mm256_broadcast_sd(&self.v[a]);
  }
  const __m256d radius = _mm256_broadcast_sd(&self.r), at = _mm256_set1_pd(now);
  __m256d least = _mm256_set1_pd(never);
  const auto scan = [&](auto with_shifts) {
    for (std::size_t c = first; c < last; c += group) {
      const __m256d t = vector_contact<D, decltype(with_shifts)::value>(flat, shifts, offset + c, shift_offset + c,
                                                                         unshifted, x, v, radius, at);
      _mm256_storeu_pd(times + c, t);
      least = _mm256_min_pd(least, t);
    }
  };
  if (shifts) scan(std::true_type{});
  else scan(std::false_type{});
  // Lanes hold times or `never`, no NaN, so the order of the minima is immaterial.
  const __m128d pair_least = _mm_min_pd(_mm256_castpd256_pd128(least), _mm256_extractf128_pd(least, 1));
  earliest = _mm_cvtsd_f64(_mm_min_sd(pair_least, _mm_unpackhi_pd(pair_least, pair_least)));
  if (earliest == never) return {never, begin};
  // The first candidate with that time, a group at a time.
  const __m256d wanted = _mm256_set1_pd(earliest);
  std::size_t position = first;
  int found;
  while ((found = _mm256_movemask_pd(_mm256_cmp_pd(_mm256_loadu_pd(times + position), wanted, _CMP_EQ_OQ))) == 0)
    position += group;
  return {earliest, position + static_cast<std::size_t>(__builtin_ctz(static_cast<unsigned>(found)))};
#else
  double xi[D], vi[D];
  for (int a = 0; a < D; ++a) {
    xi[a] = self.x[a];
    vi[a] = self.v[a];
  }
  const double ri = self.r;
  const double zero_shift[D] = {};
  for (std::size_t c = first; c < last; ++c) {
    const auto& record = *reinterpret_cast<const MotionRecord<D>*>(reinterpret_cast<const double*>(records) + offset[c]);
    const double t = scalar_contact<D>(record, shifts ? shifts + shift_offset[c] : zero_shift, xi, vi, ri, now);
    times[c] = t;
    earliest = std::min(earliest, t);
  }
  if (earliest == never) return {never, begin};
  std::size_t position = first;
  while (times[position] != earliest) ++position;
  return {earliest, position};
#endif
}

template EarliestContact earliest_contact<2>(CandidateList&, std::size_t, std::size_t, const MotionRecord<2>*,
                                             const double*, std::int32_t, const MotionRecord<2>&, double);
template EarliestContact earliest_contact<3>(CandidateList&, std::size_t, std::size_t, const MotionRecord<3>*,
                                             const double*, std::int32_t, const MotionRecord<3>&, double);

}  // namespace granflow::edmd
