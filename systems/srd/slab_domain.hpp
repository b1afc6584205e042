#pragma once
// How an SRD grid is split over K ranks: slabs of whole cells along one
// periodic axis (srd_setup.hpp picks it), rank r owning the particles whose
// coordinate along it lies in [low(r), low(r + 1)). The slabs differ by at most one
// cell, so that ranks of a homogeneous fluid carry equal work.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "engine/core/config.hpp"

namespace granflow::srd {

struct SlabDomain {
  int rank = 0;
  int ranks = 1;
  std::int64_t cells = 1;  // of the whole grid along the slab axis

  // axis_name: of the slab axis, for the message.
  SlabDomain(int this_rank, int rank_count, std::int64_t cells_along, const char* axis_name)
      : rank(this_rank), ranks(rank_count), cells(cells_along) {
    if (ranks > cells)
      throw ConfigError(fmt::format("{} ranks cannot split {} cells along {} (system.cells): a rank's slab must hold "
                                    "at least one whole cell; use at most {} ranks or more cells",
                                    ranks, cells, axis_name, cells));
  }

  std::int64_t low_of(int r) const { return cells * r / ranks; }
  std::int64_t low() const { return low_of(rank); }
  std::int64_t high() const { return low_of(rank + 1); }
  int below() const { return (rank + ranks - 1) % ranks; }
  int above() const { return (rank + 1) % ranks; }

  // The rank that owns coordinate z in [0, cells] (z = cells, a position
  // wrapped by round-off onto the far edge, is the last cell's).
  int owner(double z) const {
    const auto k = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(z)), 0, cells - 1);
    return static_cast<int>((static_cast<std::int64_t>(ranks) * (k + 1) + cells - 1) / cells - 1);
  }
};

}  // namespace granflow::srd
