#pragma once
// What the soft-sphere step over MPI ranks (dem_domain_step.hpp) hands the
// whole World, which observers and checkpoints read: every rank's own
// spheres gathered in rank order, which is the whole system's order, with
// the neighbour lists as one rank would hold them, so that a checkpoint is
// one rank's and resumes on any number of ranks.

#include <cstddef>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "components/angular_velocity.hpp"
#include "components/compartment_side.hpp"
#include "components/force.hpp"
#include "components/image_count.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/torque.hpp"
#include "components/velocity.hpp"
#include "engine/core/communicator.hpp"
#include "engine/core/world.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/geometry/cell_grid.hpp"

namespace granflow::dem {

// Each sphere's index in the whole system at the last list build (exact in
// a double below 2^53): the order of a cell's spheres at the next build.
struct WholeIndex : Column<double> {
  static constexpr const char* key = "dem_whole_index";
};

// A World's columns, looked up once per pass rather than per sphere; the
// optional ones null where the run has none.
struct DomainColumns {
  Vec<3>* x = nullptr;
  Vec<3>* v = nullptr;
  Vec<3>* f = nullptr;
  std::uint32_t* id = nullptr;
  double* mass = nullptr;
  double* radius = nullptr;
  double* index = nullptr;  // the local World's alone
  typename ImageCount<3>::value_type* image = nullptr;
  Vec<3>* omega = nullptr;
  Vec<3>* torque = nullptr;
  std::uint8_t* side = nullptr;  // where an observer keeps one (CompartmentSide)
};
// `local`: the World of one rank (whose spheres carry their WholeIndex).
inline DomainColumns columns_of(World& world, bool images, bool rotating, bool local) {
  DomainColumns c;
  c.x = world.component<Position<3>>().data();
  c.v = world.component<Velocity<3>>().data();
  c.f = world.component<Force<3>>().data();
  c.id = world.component<ParticleId>().data();
  c.mass = world.component<Mass>().data();
  c.radius = world.component<Radius>().data();
  if (local) c.index = world.component<WholeIndex>().data();
  if (images) c.image = world.component<ImageCount<3>>().data();
  if (rotating) {
    c.omega = world.component<AngularVelocity>().data();
    c.torque = world.component<Torque>().data();
  }
  if (world.has_component<CompartmentSide>()) c.side = world.component<CompartmentSide>().data();
  return c;
}

// The whole World takes the order of the gathered spheres as a
// permutation (World::permute), as the lists' builds reorder it on one
// rank, so that what follows each sphere by index (an observer's
// per-sphere state) follows it here too. `id_at`: the id's place in a
// gathered sphere's `width` values.
inline void follow_order(World& whole, const std::vector<double>& all, std::size_t width, std::size_t id_at) {
  const auto& ids = whole.component<ParticleId>().values;
  const std::size_t n = all.size() / width;
  if (ids.size() != n) return;
  std::unordered_map<std::uint32_t, std::uint32_t> was;
  was.reserve(n);
  for (std::size_t i = 0; i < n; ++i) was[ids[i]] = static_cast<std::uint32_t>(i);
  std::vector<std::uint32_t> order(n);
  bool moved = false;
  for (std::size_t k = 0; k < n; ++k) {
    const auto found = was.find(static_cast<std::uint32_t>(all[k * width + id_at]));
    if (found == was.end()) return;
    order[k] = found->second;
    moved |= order[k] != k;
  }
  if (moved) whole.permute(order);
}


// The own spheres [from, from + count) of every rank's `local` World, with
// their lists (partners by whole index), into `whole` on rank 0 (the
// others' stays as it is); `grid`: the whole system's list cells, whose
// layers the lists' slabs are. Collective.
inline void gather_whole(const Communicator& ranks, World& local, std::size_t from, std::size_t count,
                         const CellGrid<3>& grid, World& whole) {
  const auto& nl = local.resource<NeighbourList<3>>();
  const bool images = local.has_component<ImageCount<3>>(), rotating = local.has_component<AngularVelocity>();
  const std::size_t walls = nl.walls;
  const DomainColumns c = columns_of(local, images, rotating, true);
  // Per sphere: position, velocity, force, reference, id, mass, radius,
  // images, spin and torque, wall springs, its side, its pair count.
  const std::size_t width = 16 + (images ? 3 : 0) + (rotating ? 6 + 3 * walls : 0) + (c.side ? 1 : 0);
  std::vector<double> spheres, pairs;
  spheres.reserve(count * width);
  for (std::size_t i = from; i < from + count; ++i) {
    const auto add = [&](const auto& vec) { spheres.insert(spheres.end(), vec.data(), vec.data() + 3); };
    add(c.x[i]);
    add(c.v[i]);
    add(c.f[i]);
    add(nl.reference[i]);
    spheres.push_back(c.id[i]);
    spheres.push_back(c.mass[i]);
    spheres.push_back(c.radius[i]);
    if (c.image)
      for (int a = 0; a < 3; ++a) spheres.push_back(c.image[i][a]);
    if (c.omega) {
      add(c.omega[i]);
      add(c.torque[i]);
      for (std::size_t w = 0; w < walls; ++w) add(nl.wall_shear[i * walls + w]);
    }
    if (c.side) spheres.push_back(c.side[i]);
    const auto [begin, end] = nl.pairs_of(i);
    spheres.push_back(end - begin);
    for (std::uint32_t p = begin; p < end; ++p) {
      pairs.push_back(c.index[nl.list[p]]);
      if (nl.keeps_history) pairs.insert(pairs.end(), nl.shear[p].begin(), nl.shear[p].end());
    }
  }
  const std::vector<double> all = ranks.gather_to_first(spheres);
  const std::vector<double> all_pairs = ranks.gather_to_first(pairs);
  if (ranks.rank() > 0) return;
  const std::size_t n = all.size() / width;
  follow_order(whole, all, width, 12);
  whole.resize(n);
  auto& whole_nl = whole.resource<NeighbourList<3>>();
  whole_nl.reference.resize(n);
  whole_nl.order.resize(n);
  std::iota(whole_nl.order.begin(), whole_nl.order.end(), 0u);
  whole_nl.offsets.assign(n + 1, 0);
  whole_nl.wall_shear.assign(whole_nl.keeps_history ? n * walls : 0, Shear{});
  std::vector<std::uint32_t> per_layer(static_cast<std::size_t>(grid.cells(2)) + 1, 0);
  const DomainColumns w = columns_of(whole, images, rotating, false);
  for (std::size_t i = 0; i < n; ++i) {
    const double* d = all.data() + i * width;
    w.x[i] = Vec<3>(d[0], d[1], d[2]);
    w.v[i] = Vec<3>(d[3], d[4], d[5]);
    w.f[i] = Vec<3>(d[6], d[7], d[8]);
    whole_nl.reference[i] = Vec<3>(d[9], d[10], d[11]);
    w.id[i] = static_cast<std::uint32_t>(d[12]);
    w.mass[i] = d[13];
    w.radius[i] = d[14];
    std::size_t k = 15;
    if (w.image) {
      for (int a = 0; a < 3; ++a) w.image[i][a] = static_cast<std::int32_t>(d[k + static_cast<std::size_t>(a)]);
      k += 3;
    }
    if (w.omega) {
      w.omega[i] = Vec<3>(d[k], d[k + 1], d[k + 2]);
      w.torque[i] = Vec<3>(d[k + 3], d[k + 4], d[k + 5]);
      k += 6;
      for (std::size_t wall = 0; wall < walls; ++wall, k += 3)
        whole_nl.wall_shear[i * walls + wall] = {d[k], d[k + 1], d[k + 2]};
    }
    if (c.side) {
      if (w.side) w.side[i] = static_cast<std::uint8_t>(d[k]);
      ++k;
    }
    whole_nl.offsets[i + 1] = whole_nl.offsets[i] + static_cast<std::uint32_t>(d[k]);
    ++per_layer[grid.cell_of(whole_nl.reference[i]) / grid.stride(2) + 1];
  }
  const std::size_t stride = whole_nl.keeps_history ? 4 : 1;
  whole_nl.list.resize(all_pairs.size() / stride);
  whole_nl.shear.assign(whole_nl.keeps_history ? whole_nl.list.size() : 0, Shear{});
  for (std::size_t p = 0; p < whole_nl.list.size(); ++p) {
    whole_nl.list[p] = static_cast<std::uint32_t>(all_pairs[p * stride]);
    if (whole_nl.keeps_history)
      whole_nl.shear[p] = {all_pairs[p * stride + 1], all_pairs[p * stride + 2], all_pairs[p * stride + 3]};
  }
  for (std::size_t s = 1; s < per_layer.size(); ++s) per_layer[s] += per_layer[s - 1];
  whole_nl.slabs = per_layer;
  whole_nl.periodic_slabs = false;
  whole_nl.builds = nl.builds;
  whole_nl.derive();
}

// The lists of this rank's own spheres [from, from + count) of its `local`
// World, in the whole system's numbering, into `part` (a checkpoint's rows
// by rank, NeighbourList::part_of_whole): the spheres' whole indices, their
// partners' and springs, their reference positions, and the whole system's
// slabs of `grid`'s layers, counted over the ranks. Collective.
inline void lend_lists_of_part(const Communicator& ranks, World& local, std::size_t from, std::size_t count,
                               const CellGrid<3>& grid, NeighbourList<3>& part) {
  const auto& nl = local.resource<NeighbourList<3>>();
  const auto& index = local.component<WholeIndex>();
  const std::size_t walls = nl.walls;
  part.release();
  part.part_of_whole = true;
  part.builds = nl.builds;
  part.order.resize(count);
  part.offsets.assign(count + 1, 0);
  part.reference.assign(nl.reference.begin() + static_cast<std::ptrdiff_t>(from),
                        nl.reference.begin() + static_cast<std::ptrdiff_t>(from + count));
  if (nl.keeps_history)
    part.wall_shear.assign(nl.wall_shear.begin() + static_cast<std::ptrdiff_t>(from * walls),
                           nl.wall_shear.begin() + static_cast<std::ptrdiff_t>((from + count) * walls));
  std::vector<double> per_layer(static_cast<std::size_t>(grid.cells(2)), 0.0);
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = from + k;
    part.order[k] = static_cast<std::uint32_t>(index[i]);
    const auto [begin, end] = nl.pairs_of(i);
    for (std::uint32_t p = begin; p < end; ++p) {
      part.list.push_back(static_cast<std::uint32_t>(index[nl.list[p]]));
      if (nl.keeps_history) part.shear.push_back(nl.shear[p]);
    }
    part.offsets[k + 1] = static_cast<std::uint32_t>(part.list.size());
    per_layer[grid.cell_of(nl.reference[i]) / grid.stride(2)] += 1.0;
  }
  per_layer = ranks.add_across(per_layer);
  part.slabs.assign(per_layer.size() + 1, 0);
  for (std::size_t s = 0; s < per_layer.size(); ++s)
    part.slabs[s + 1] = part.slabs[s] + static_cast<std::uint32_t>(per_layer[s]);
  part.periodic_slabs = false;
}

}  // namespace granflow::dem
