#pragma once
// The earliest contact of one particle among a range of candidates: the inner
// loop of every event prediction. Every candidate is tested without early
// exits, so the loop runs as vector instructions (the candidates' records
// gathered straight from the motion records, a vector square root) in a file
// compiled for the machine's instruction set; then the earliest is picked in
// the order of the list, so ties go to the first candidate exactly as in a
// sequential scan.

#include <cstddef>
#include <cstdint>

#include "systems/edmd/candidate_list.hpp"
#include "systems/edmd/motion_record.hpp"

namespace granflow::edmd {

struct EarliestContact {
  double time;           // absolute; infinite when no candidate approaches
  std::size_t position;  // in the candidate list
};

// Candidates [begin, end) of the list, whose records are `records` (each at
// its own local time, moved here to `now`) and whose periodic shifts are in
// `shifts` (at offset `unshifted` the zero shift; null where the list was
// written without shifts: none is seen through an image), against `self`,
// which is at time `now`.
template <int D>
EarliestContact earliest_contact(CandidateList& candidates, std::size_t begin, std::size_t end,
                                 const MotionRecord<D>* records, const double* shifts, std::int32_t unshifted,
                                 const MotionRecord<D>& self, double now);

extern template EarliestContact earliest_contact<2>(CandidateList&, std::size_t, std::size_t, const MotionRecord<2>*,
                                                    const double*, std::int32_t, const MotionRecord<2>&, double);
extern template EarliestContact earliest_contact<3>(CandidateList&, std::size_t, std::size_t, const MotionRecord<3>*,
                                                    const double*, std::int32_t, const MotionRecord<3>&, double);

}  // namespace granflow::edmd
