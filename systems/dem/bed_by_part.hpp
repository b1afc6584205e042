#pragma once
// A fresh bed over MPI ranks is made by parts, so that no rank holds the
// whole: every rank lists every initial site (cheap: a position each), but
// creates only the spheres of its share, a slab of the neighbour-list
// layers along z (the layers of dem_domain_step.hpp) split by sphere count
// as the step's balance splits it. The step then starts from the parts
// (DemDomainStep): it settles the slabs, passes on any sphere another rank
// owns, and builds the lists and the first forces over the ranks. A resumed
// run reads its part too (resumed_part.hpp); a stored start still reads the
// whole on every rank.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "components/box.hpp"
#include "components/vector.hpp"
#include "engine/core/communicator.hpp"
#include "engine/core/config.hpp"
#include "engine/core/world.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/geometry/cell_grid.hpp"
#include "systems/geometry/slab_domain.hpp"

namespace granflow::dem {

// In the World of a rank that holds only its part of a fresh bed: how many
// spheres the whole bed has.
struct BedByPart {
  static constexpr const char* key = "dem_bed_by_part";
  std::size_t spheres = 0;
};

// In the World of a rank that resumed only its part (resumed_part.hpp).
struct ResumedPart {
  static constexpr const char* key = "dem_resumed_part";
  std::size_t spheres = 0;                // the whole system's
  std::size_t first = 0, count = 0;       // the spheres' rows read: [first, first + count)
  std::size_t first_pair = 0, pairs = 0;  // and their pairs'
  std::vector<std::int64_t> bounds;       // the slabs they were read for
};

// The whole system's list cells, whose layers along z the ranks' slabs are
// made of: as the lists build them for `spheres` spheres of at most
// `largest_radius`.
inline CellGrid<3> domain_layers(const std::array<double, 3>& edges, const std::array<bool, 3>& periodic,
                                 double largest_radius, double skin, std::size_t spheres) {
  Box<3> box;
  box.length = edges;
  box.periodic = periodic;
  return list_cells(box, 2.0 * largest_radius + skin, spheres);
}

// What sets the layers, for a refusal of more ranks than layers.
inline constexpr const char* domain_layers_from =
    "the neighbour-list cells, each at least 2 particle.radius + neighbour.skin high, of system.box";

// The slab each rank starts with: the layers split so that each holds
// about as many of `sites` (where balance.every_steps > 0; else equal slabs).
inline SlabDomain starting_slabs(const Communicator& ranks, const CellGrid<3>& layers, const std::vector<Vec<3>>& sites,
                                 bool balanced) {
  SlabDomain slab(ranks.rank(), ranks.size(), layers.cells(2), "z", domain_layers_from);
  if (!balanced) return slab;
  std::vector<double> per_layer(static_cast<std::size_t>(layers.cells(2)), 0.0);
  for (const Vec<3>& x : sites) per_layer[layers.cell_of(x) / layers.stride(2)] += 1.0;
  slab.bounds = SlabDomain::balanced(per_layer, ranks.size());
  return slab;
}

// The indices of `sites` this process creates: all of them on one process;
// over ranks, those in its starting slab. `radius`: every sphere's.
inline std::vector<std::size_t> sites_made_here(const Config& c, const Communicator* ranks,
                                                const std::array<double, 3>& edges,
                                                const std::array<bool, 3>& periodic, const std::vector<Vec<3>>& sites,
                                                double radius) {
  std::vector<std::size_t> made;
  if (!ranks || ranks->size() < 2) {
    made.resize(sites.size());
    for (std::size_t i = 0; i < sites.size(); ++i) made[i] = i;
    return made;
  }
  const CellGrid<3> layers =
      domain_layers(edges, periodic, radius, c.real("neighbour.skin") * radius, sites.size());
  const SlabDomain slab = starting_slabs(*ranks, layers, sites, c.integer("balance.every_steps") > 0);
  for (std::size_t i = 0; i < sites.size(); ++i)
    if (slab.owner(static_cast<double>(layers.cell_of(sites[i]) / layers.stride(2))) == slab.rank) made.push_back(i);
  return made;
}

}  // namespace granflow::dem
