#pragma once
// The earliest contact of one particle among a list of candidates: the inner
// loop of every event prediction. Every candidate is tested without early
// exits, so the loop runs as vector instructions (gathers, a vector square
// root) in a file compiled for the machine's instruction set; then the
// earliest is picked in the order of the list, so ties go to the first
// candidate exactly as in a sequential scan.

#include <cstddef>
#include <cstdint>

#include "components/vector.hpp"
#include "systems/edmd/motion_record.hpp"

namespace granflow::edmd {

struct EarliestContact {
  double time;          // absolute; infinite when no candidate approaches
  std::size_t position;  // in the candidate list
};

// `self` is at time `now`; candidate c is records[candidates[c]] seen through
// the periodic image shifts[slots[c]] (slots and shifts may be null: no shift).
// `times` has room for `count` entries.
template <int D>
EarliestContact earliest_contact(const MotionRecord<D>* records, const std::uint32_t* candidates,
                                 const std::uint8_t* slots, const Vec<D>* shifts, std::size_t count,
                                 const MotionRecord<D>& self, double now, double* times);

extern template EarliestContact earliest_contact<2>(const MotionRecord<2>*, const std::uint32_t*,
                                                    const std::uint8_t*, const Vec<2>*, std::size_t,
                                                    const MotionRecord<2>&, double, double*);
extern template EarliestContact earliest_contact<3>(const MotionRecord<3>*, const std::uint32_t*,
                                                    const std::uint8_t*, const Vec<3>*, std::size_t,
                                                    const MotionRecord<3>&, double, double*);

}  // namespace granflow::edmd
