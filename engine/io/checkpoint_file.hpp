#pragma once
// A checkpoint file: an H5MD file with the resolved configuration under
// /parameters and the run's state (engine/core/state_map.hpp) as a list of named
// arrays, /checkpoint/names and /checkpoint/values/<index>. Written as
// .partial and renamed, so a checkpoint on disk is always complete.

#include <string>

#include "engine/core/config.hpp"
#include "engine/core/state_map.hpp"

namespace granflow {

void write_checkpoint(const std::string& path, const std::string& scenario, const Config& config,
                      const StateMap& state);

struct CheckpointContents {
  std::string configuration;  // resolved TOML it was written with
  StateMap state;
};
// Throws InputError naming the file when it cannot be read as a checkpoint.
CheckpointContents read_checkpoint(const std::string& path);

}  // namespace granflow
