#pragma once
// How one system's cells are split over K MPI ranks: slabs of whole layers
// of cells along one axis (an SRD grid along a periodic axis, srd_setup.hpp;
// the soft spheres' neighbour cells along z, dem_domain_step.hpp), rank r
// owning the particles whose layer lies in [low(r), low(r + 1)). The slabs
// start equal (differing by at most one layer); where the particles gather
// unevenly (clusters, a bed under gravity), `balanced` moves the bounds so
// that each rank carries about the same load, as LAMMPS's `balance` does
// along one dimension.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/core/config.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/units.hpp"

namespace granflow {

struct SlabDomain {
  int rank = 0;
  int ranks = 1;
  std::int64_t cells = 1;  // of the whole grid along the slab axis
  // Rank r owns the layers of cells [bounds[r], bounds[r + 1]).
  std::vector<std::int64_t> bounds;

  // axis_name: of the slab axis, cells_from: what sets the cells (both for
  // the message). The slabs start equal.
  SlabDomain(int this_rank, int rank_count, std::int64_t cells_along, const char* axis_name,
             const char* cells_from = "system.cells")
      : rank(this_rank), ranks(rank_count), cells(cells_along) {
    if (ranks > cells)
      throw ConfigError(fmt::format("{} ranks cannot split {} cells along {} ({}): a rank's slab must hold "
                                    "at least one whole cell; use at most {} ranks or more cells",
                                    ranks, cells, axis_name, cells_from, cells));
    for (int r = 0; r <= ranks; ++r) bounds.push_back(cells * r / ranks);
  }

  std::int64_t low_of(int r) const { return bounds[static_cast<std::size_t>(r)]; }
  std::int64_t low() const { return low_of(rank); }
  std::int64_t high() const { return low_of(rank + 1); }
  int below() const { return (rank + ranks - 1) % ranks; }
  int above() const { return (rank + 1) % ranks; }

  // The rank that owns coordinate z in [0, cells] (z = cells, a position
  // wrapped by round-off onto the far edge, is the last cell's).
  int owner(double z) const {
    const auto k = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(z)), 0, cells - 1);
    return static_cast<int>(std::upper_bound(bounds.begin() + 1, bounds.end(), k) - (bounds.begin() + 1));
  }

  // Bounds that give every rank about the same load: `per_layer` holds the
  // load of each layer of cells; rank r's slab starts at the first layer
  // before which r / K of it lies, and holds at least one layer.
  static std::vector<std::int64_t> balanced(const std::vector<double>& per_layer, int ranks) {
    const auto cells = static_cast<std::int64_t>(per_layer.size());
    double total = 0.0;
    for (double n : per_layer) total += n;
    std::vector<std::int64_t> out{0};
    double below = 0.0;
    std::int64_t layer = 0;
    for (int r = 1; r < ranks; ++r) {
      const double target = total * r / ranks;
      while (layer < cells && below + per_layer[static_cast<std::size_t>(layer)] <= target)
        below += per_layer[static_cast<std::size_t>(layer++)];
      out.push_back(std::clamp(layer, out.back() + 1, cells - (ranks - r)));
    }
    out.push_back(cells);
    return out;
  }
  // Whether `bounds` leave the busiest rank more than `threshold` times
  // the mean load (and there is a load at all).
  static bool uneven(const std::vector<double>& per_layer, const std::vector<std::int64_t>& bounds, double threshold) {
    const std::vector<double> each = loads(per_layer, bounds);
    double total = 0.0, busiest = 0.0;
    for (double load : each) {
      total += load;
      busiest = std::max(busiest, load);
    }
    return total > 0.0 && busiest > threshold * total / static_cast<double>(each.size());
  }
  // Each rank's load under `bounds`, from the layers'.
  static std::vector<double> loads(const std::vector<double>& per_layer, const std::vector<std::int64_t>& bounds) {
    std::vector<double> out(bounds.empty() ? 0 : bounds.size() - 1, 0.0);
    for (std::size_t r = 0; r + 1 < bounds.size(); ++r)
      for (auto k = bounds[r]; k < bounds[r + 1]; ++k) out[r] += per_layer[static_cast<std::size_t>(k)];
    return out;
  }
};

// When the slabs are rebalanced over MPI ranks: how often each rank's load
// is counted (`load`: what it counts, for the description) and how uneven
// it may grow. Declared once for every method that spreads a system so.
inline void declare_slab_balance_keys(ConfigSchema& s, std::int64_t every_steps, double threshold, const char* load) {
  s.integer("balance.every_steps", every_steps, 0, 1000000000000,
            fmt::format("over MPI ranks: steps between counting each rank's load, {} (0: the slabs stay equal)", load))
      .real("balance.threshold", threshold, 1.0, std::numeric_limits<double>::infinity(),
            "over MPI ranks: move the slabs' bounds when the busiest rank's load exceeds this times the mean");
  s.unit("balance.threshold", unit::none);
}

// The slab bounds a checkpoint carries, so that a run resumed on as many
// ranks continues with the bounds it had (and stays bit for bit the same).
struct SlabBounds : Stateful {
  std::vector<std::int64_t> bounds;
  StateMap save_state() const override { return {{"bounds", std::vector<double>(bounds.begin(), bounds.end())}}; }
  void restore_state(const StateMap& state) override {
    bounds.clear();
    const auto found = state.find("bounds");
    if (found == state.end()) return;  // a checkpoint from before the bounds were kept
    for (double b : found->second) bounds.push_back(static_cast<std::int64_t>(b));
  }
};

}  // namespace granflow
