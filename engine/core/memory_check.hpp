#pragma once
// Fails fast, before allocating, when a run would need more memory than the
// machine has available, naming the key that sets its size.

#include <cstdio>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "engine/core/input_error.hpp"

namespace granflow {

// MemAvailable of /proc/meminfo, in bytes; 0 where it cannot be read.
inline double available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string name;
  double kib = 0;
  std::string unit;
  while (meminfo >> name >> kib >> unit)
    if (name == "MemAvailable:") return kib * 1024.0;
  return 0.0;
}

// `what` names the setting, e.g. "system.count = 2000000000".
inline void require_memory(const std::string& what, double bytes) {
  const double available = available_memory_bytes();
  if (available > 0 && bytes > available)
    throw InputError(fmt::format("{} needs about {:.3g} GB of memory, but {:.3g} GB are available; lower it", what,
                                 bytes / 1e9, available / 1e9));
}

}  // namespace granflow
