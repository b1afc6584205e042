#pragma once
// A particle state stored by another run or another code, to start a run
// from (`initial.from`, `initial.frame`): a frame of a granflow result file
// (H5MD), of a GSD file in the HOOMD schema (HOOMD-blue, gsd, OVITO) or of an
// extended XYZ file (ASE, OVITO), told apart by their contents.
//
// Positions come back in granflow's box [0, L) along each axis: GSD's box is
// centred on the origin, so L/2 is added. Where a format has a default
// (HOOMD's mass 1, diameter 1, velocity 0, type 0) a missing column takes it;
// otherwise a missing column is left empty for the caller to refuse.

#include <cstdint>
#include <string>
#include <vector>

namespace granflow {

struct StoredState {
  std::string source;  // "FILE, frame K of M", for messages
  std::size_t dimension = 3;
  std::size_t count = 0;
  std::vector<double> edges;
  std::vector<bool> periodic;       // per axis
  std::vector<double> position;     // count x dimension
  std::vector<double> velocity;     // count x dimension, or empty
  std::vector<double> radius;       // count, or empty
  std::vector<double> mass;         // count, or empty
  std::vector<std::int64_t> species;  // count, or empty
};

// Frame `frame` of the file (negative: counted from the end, -1 the last).
// Throws InputError naming the file and what is wrong with it.
StoredState read_stored_state(const std::string& path, std::int64_t frame);

}  // namespace granflow
