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

// The same frame for a reader that never holds all its particles (one
// system over MPI ranks, each keeping its own): the layout, and the
// positions and velocities by rows on demand. A granflow result file keeps
// them in the file, read by hyperslab; GSD and extended XYZ files are read
// whole once.
class StoredFrame {
 public:
  StoredFrame(const std::string& path, std::int64_t frame);
  // All of the state but a result file's positions and velocities.
  const StoredState& layout() const { return state_; }
  bool has_velocity() const { return has_velocity_; }
  // Rows [first, first + count), `dimension` values each.
  std::vector<double> positions(std::size_t first, std::size_t count) const {
    return rows("position", state_.position, first, count);
  }
  std::vector<double> velocities(std::size_t first, std::size_t count) const {
    return rows("velocity", state_.velocity, first, count);
  }

 private:
  std::vector<double> rows(const char* column, const std::vector<double>& held, std::size_t first,
                           std::size_t count) const;
  std::string path_;
  bool in_file_ = false;
  std::size_t frame_ = 0;
  bool has_velocity_ = false;
  StoredState state_;
};

}  // namespace granflow
