#pragma once
// A checkpoint file: an H5MD file with the resolved configuration under
// /parameters and the run's state (engine/core/state_map.hpp) as a list of named
// arrays, /checkpoint/names and /checkpoint/values/<index>. Written as
// .partial and renamed, so a checkpoint on disk is always complete.
//
// One system over MPI ranks writes and reads the arrays that hold a row per
// particle (the World's columns) in blocks of rows, so that no rank holds
// the whole system for a checkpoint: rank 0 writes each block as the ranks
// send it, and on resume each rank keeps the rows of its own domain. The
// file is the same as one process writes.

#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/communicator.hpp"
#include "engine/core/config.hpp"
#include "engine/core/state_map.hpp"

namespace granflow {

void write_checkpoint(const std::string& path, const std::string& scenario, const Config& config,
                      const StateMap& state);

// Whether a checkpoint array holds one row per particle, or per item of a
// rank's part that a kept object gives (Stateful::state_rows): the World's
// columns, "world/<key>" (not their ".width"), and a kept object's
// "kept/<name>/rows/<key>".
bool holds_particle_rows(const std::string& name);

// This rank's rows of the particle arrays: `count` rows of each, or as many
// as `counts` gives for an array whose rows are not the particles (a kept
// object's per-pair lists). In the file the ranks' rows follow one another
// in rank order.
struct RankRows {
  std::size_t count = 0;
  StateMap arrays;
  std::map<std::string, std::size_t> counts;
  std::size_t rows_of(const std::string& name) const {
    const auto found = counts.find(name);
    return found == counts.end() ? count : found->second;
  }
};

// The same file as write_checkpoint of `state` with every rank's `rows`
// gathered, written without gathering them: every rank calls it
// (collective), rank 0 writes the file, receiving the rows block by block.
// `state` is read on rank 0 only.
void write_checkpoint_by_rank(const std::string& path, const std::string& scenario, const Config& config,
                              const StateMap& state, const RankRows& rows, const Communicator& ranks);

// The particle arrays of a checkpoint left in the file, read by block.
class CheckpointRows {
 public:
  CheckpointRows() = default;
  explicit CheckpointRows(std::string file) : file_(std::move(file)) {}
  void add(const std::string& name, std::string dataset, std::size_t size) {
    datasets_[name] = {std::move(dataset), size};
  }
  bool empty() const { return datasets_.empty(); }
  bool holds(const std::string& name) const { return datasets_.count(name) != 0; }
  // name -> values it holds
  std::map<std::string, std::size_t> sizes() const;
  std::vector<double> read(const std::string& name, std::size_t first, std::size_t count) const;

 private:
  struct Dataset {
    std::string path;
    std::size_t size = 0;
  };
  std::string file_;
  std::map<std::string, Dataset> datasets_;
};

struct CheckpointContents {
  std::string configuration;  // resolved TOML it was written with
  StateMap state;
  CheckpointRows rows;  // the particle arrays, where they were left in the file
};

struct CheckpointReading {
  // Leave the particle arrays in the file (in `rows`) instead of in `state`.
  bool particle_rows_by_block = false;
  // Check the file's seal and its checksum, the latter reading the
  // particle arrays through once in blocks: over ranks, rank 0 does it for
  // all before the others read.
  bool check = true;
};

// Throws InputError naming the file when it cannot be read as a checkpoint.
CheckpointContents read_checkpoint(const std::string& path, const CheckpointReading& how = {});

}  // namespace granflow
