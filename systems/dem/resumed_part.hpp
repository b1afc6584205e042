#pragma once
// A soft-sphere run resumed over MPI ranks reads its part of the
// checkpoint, not the whole. The checkpoint holds the spheres in the whole
// system's cell order, layer by layer along z (the lists' `slabs` count
// each layer's spheres), and their lists as rows (NeighbourList's
// rows/...: each sphere's pair count, its partners' whole indices and
// springs, its reference position). Each rank works out the slabs the step
// starts with, as the step would from the whole (each layer's load, two
// per sphere and one per listed pair, from the pair counts read block by
// block), and reads the rows of the layers it holds: its slab's and one
// either side. The step takes them as its part (DemDomainStep::scatter).
// No rank holds the whole.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/core/config.hpp"
#include "engine/core/world.hpp"
#include "engine/io/checkpoint_file.hpp"
#include "engine/run/run.hpp"
#include "systems/dem/bed_by_part.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/geometry/slab_domain.hpp"

namespace granflow::dem {

// The name the run keeps the lists under (Run::keep), and so their rows'.
inline constexpr const char* kept_lists = "neighbours";

namespace detail {
inline std::string lists_row(const std::string& name) { return std::string("kept/") + kept_lists + "/rows/" + name; }
}  // namespace detail

// The part this rank reads where the run resumes over ranks from a
// checkpoint that left the lists' rows in the file; none otherwise (then
// every rank reads the whole).
inline std::optional<ResumedPart> part_to_resume(const Run& run) {
  const Communicator* ranks = run.communicator();
  const CheckpointRows* rows = run.resumed_rows();
  const std::string counts_name = detail::lists_row("pair_counts");
  if (!ranks || ranks->size() < 2 || !run.resuming() || !rows || !rows->holds(counts_name)) return std::nullopt;
  const StateMap kept = run.kept_state(kept_lists);
  const auto found = kept.find("slabs");
  if (found == kept.end() || found->second.size() < 2) throw std::invalid_argument("checkpoint lists have no slabs");
  std::vector<std::size_t> slabs;
  for (const double s : found->second) slabs.push_back(static_cast<std::size_t>(s));
  const std::size_t n = slabs.back(), layers = slabs.size() - 1;
  if (rows->sizes().at(counts_name) != n) throw std::invalid_argument("checkpoint neighbour lists are inconsistent");
  // Each layer's listed pairs, read block by block.
  std::vector<double> pairs_in(layers, 0.0);
  constexpr std::size_t rows_per_read = std::size_t{1} << 18;
  std::size_t layer = 0;
  for (std::size_t first = 0; first < n; first += rows_per_read) {
    const std::vector<double> counts = rows->read(counts_name, first, std::min(rows_per_read, n - first));
    for (std::size_t k = 0; k < counts.size(); ++k) {
      while (first + k >= slabs[layer + 1]) ++layer;
      pairs_in[layer] += counts[k];
    }
  }
  const Config& c = run.config();
  SlabDomain slab(ranks->rank(), ranks->size(), static_cast<std::int64_t>(layers), "z", domain_layers_from);
  if (c.integer("balance.every_steps") > 0) {
    std::vector<double> load(layers);
    for (std::size_t s = 0; s < layers; ++s) load[s] = 2.0 * static_cast<double>(slabs[s + 1] - slabs[s]) + pairs_in[s];
    if (SlabDomain::uneven(load, slab.bounds, c.real("balance.threshold")))
      slab.bounds = SlabDomain::balanced(load, ranks->size());
  }
  const auto low = static_cast<std::size_t>(slab.low()), high = static_cast<std::size_t>(slab.high());
  const std::size_t held_first = low > 0 ? low - 1 : low, held_end = high < layers ? high + 1 : high;
  ResumedPart part;
  part.spheres = n;
  part.first = slabs[held_first];
  part.count = slabs[held_end] - part.first;
  for (std::size_t s = 0; s < held_first; ++s) part.first_pair += static_cast<std::size_t>(pairs_in[s]);
  for (std::size_t s = held_first; s < held_end; ++s) part.pairs += static_cast<std::size_t>(pairs_in[s]);
  part.bounds = slab.bounds;
  return part;
}

// The initial state: `create` on a fresh run; a resumed one over ranks
// reads its part where it can (ResumedPart in the World), else the whole.
inline void start_or_resume(Run& run, const std::function<void(World&)>& create) {
  const std::optional<ResumedPart> part = part_to_resume(run);
  Run::OwnedOnResume owned;
  if (part) owned.rows = std::pair{part->first, part->count};
  run.initial_state(create, owned);
  if (part) run.world().emplace_resource<ResumedPart>(*part);
}

// The lists of the part's spheres from the checkpoint's rows, in the
// whole system's numbering (NeighbourList::part_of_whole), after the run
// restored their slabs (Run::keep).
inline void read_lists_of_part(const Run& run, const ResumedPart& part, NeighbourList<3>& nl) {
  const CheckpointRows& rows = *run.resumed_rows();
  const auto sizes = rows.sizes();
  const std::size_t whole_pairs = sizes.at(detail::lists_row("list"));
  // Rows [first, first + count) of an array of `per_row` rows: its values.
  const auto read = [&](const char* name, std::size_t first, std::size_t count, std::size_t of) {
    const std::string array = detail::lists_row(name);
    const std::size_t values = sizes.at(array), width = of > 0 ? values / of : 0;
    if (width * of != values) throw std::invalid_argument("checkpoint neighbour lists are inconsistent");
    return rows.read(array, first * width, count * width);
  };
  const auto indices = [](const std::vector<double>& in, std::vector<std::uint32_t>& out) {
    out.assign(in.size(), 0);
    for (std::size_t k = 0; k < in.size(); ++k) out[k] = static_cast<std::uint32_t>(in[k]);
  };
  indices(read("order", part.first, part.count, part.spheres), nl.order);
  const std::vector<double> counts = read("pair_counts", part.first, part.count, part.spheres);
  nl.offsets.assign(part.count + 1, 0);
  for (std::size_t m = 0; m < part.count; ++m) nl.offsets[m + 1] = nl.offsets[m] + static_cast<std::uint32_t>(counts[m]);
  indices(read("list", part.first_pair, part.pairs, whole_pairs), nl.list);
  nl.reference.resize(part.count);
  unflatten_vectors(read("reference", part.first, part.count, part.spheres), nl.reference,
                    "neighbour-list reference positions");
  NeighbourList<3>::unflatten_shears(read("wall_shear", part.first, part.count, part.spheres), nl.wall_shear);
  NeighbourList<3>::unflatten_shears(read("shear", part.first_pair, part.pairs, whole_pairs), nl.shear);
  if (nl.offsets.back() != part.pairs || nl.list.size() != part.pairs)
    throw std::invalid_argument("checkpoint neighbour lists are inconsistent");
  nl.part_of_whole = true;
}

}  // namespace granflow::dem
