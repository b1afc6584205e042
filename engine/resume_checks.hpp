#pragma once
// What every --resume checks before it trusts a checkpoint: that there is one,
// and that it was written with the configuration being run.

#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "engine/config.hpp"

namespace granflow {

inline void require_checkpoint(const std::string& path) {
  if (!std::filesystem::exists(path))
    throw ConfigError(fmt::format("--resume: there is no checkpoint '{}' to resume from", path));
}

// `stored` is the configuration TOML the checkpoint was written with.
inline void require_same_configuration(const std::string& path, const std::string& stored, const Config& config) {
  if (stored != config.to_toml())
    throw ConfigError(fmt::format("--resume: checkpoint '{}' was written with a different configuration; resume with "
                                  "the same file and --set options, or delete the checkpoint",
                                  path));
}

}  // namespace granflow
