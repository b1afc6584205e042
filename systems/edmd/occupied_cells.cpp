#include "systems/edmd/occupied_cells.hpp"

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace granflow::edmd {

std::uint64_t occupied_cells(const std::int32_t* head, std::uint32_t origin, const std::int32_t* offsets, int count,
                             std::int32_t* heads) {
  const std::int32_t* base = head + origin;
  std::uint64_t occupied = 0;
#if defined(__AVX2__)
  const __m256i empty = _mm256_set1_epi32(-1);
  for (int k = 0; k < count; k += occupancy_group) {
    const __m256i at = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(offsets + k));
    const __m256i found = _mm256_i32gather_epi32(base, at, 4);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(heads + k), found);
    const auto bits = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(found, empty))));
    occupied |= static_cast<std::uint64_t>(bits) << k;
  }
#else
  for (int k = 0; k < count; ++k) {
    heads[k] = base[offsets[k]];
    occupied |= static_cast<std::uint64_t>(heads[k] >= 0) << k;
  }
#endif
  return count == 64 ? occupied : occupied & ((std::uint64_t{1} << count) - 1);
}

}  // namespace granflow::edmd
