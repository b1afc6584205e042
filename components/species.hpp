#pragma once
// Species label, used to split observables of mixtures.
#include <cstdint>

#include "engine/core/world.hpp"

namespace granflow {
struct Species : Column<std::uint32_t> {
  static constexpr const char* key = "species";
};
}  // namespace granflow
