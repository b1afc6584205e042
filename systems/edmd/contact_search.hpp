#pragma once
// The earliest contact of one particle among a range of candidates: the inner
// loop of every event prediction. Every candidate is tested without early
// exits, so the loop runs as vector instructions (contiguous loads, a vector
// square root) in a file compiled for the machine's instruction set; then the
// earliest is picked in the order of the buffer, so ties go to the first
// candidate exactly as in a sequential scan.

#include <cstddef>

#include "systems/edmd/candidate_buffer.hpp"
#include "systems/edmd/motion_record.hpp"

namespace granflow::edmd {

struct EarliestContact {
  double time;           // absolute; infinite when no candidate approaches
  std::size_t position;  // in the candidate buffer
};

// Candidates [begin, end) of the buffer, seen at time `now`, against `self`,
// which is at that time too.
template <int D>
EarliestContact earliest_contact(CandidateBuffer<D>& candidates, std::size_t begin, std::size_t end,
                                 const MotionRecord<D>& self, double now);

extern template EarliestContact earliest_contact<2>(CandidateBuffer<2>&, std::size_t, std::size_t,
                                                    const MotionRecord<2>&, double);
extern template EarliestContact earliest_contact<3>(CandidateBuffer<3>&, std::size_t, std::size_t,
                                                    const MotionRecord<3>&, double);

}  // namespace granflow::edmd
