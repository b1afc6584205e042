#pragma once
// Verlet neighbour lists of soft spheres (a World resource and the system
// that keeps it). Half lists: each pair of spheres whose surfaces are
// within the skin is listed once, under the sphere that comes first in cell
// order. The lists are rebuilt from a cell grid (cells at least one
// interaction range wide, a counting sort, the 3^D neighbouring cells) only
// when some sphere has moved more than half the skin since the last build:
// then no pair can have come into contact unlisted. Rebuilds are counted.
// At a rebuild the spheres can be put in cell order (World::permute,
// `reorder`): neighbours then sit close in memory. The lists are stored in
// cell order and cut into slabs, one layer of cells along the last axis
// each: a slab's pairs reach only into itself and the next slab (the first
// slab's also into the last along a periodic axis), so the force pass can
// give every pair's force to both its spheres, slabs of one parity at a
// time in parallel, without atomics and in the same order on any thread
// count. The tangential-spring history of each contact follows its
// pair through rebuilds and reorderings. Each build also holds the spheres
// to the walls' reach (the watchdog, dem_watchdog.hpp).

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "components/box.hpp"
#include "components/clock.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/run/run_control.hpp"
#include "systems/dem/dem_watchdog.hpp"
#include "systems/dem/nearest_image.hpp"
#include "systems/dem/thread_domains.hpp"
#include "systems/geometry/cell_grid.hpp"
#include "systems/geometry/counting_sort.hpp"

namespace granflow::dem {

inline const SystemDescription dem_neighbour_list_description{
    "dem_neighbour_list",
    "half Verlet lists with a skin from a cell grid, rebuilt (spheres put in cell order) when one moved half the skin"};

// The tangential spring of one contact (Cundall-Strack): the displacement
// of the first sphere's contact point relative to the second's (or to the
// wall's) accumulated while they touch; zero out of contact.
using Shear = std::array<double, 3>;

template <int D>
struct NeighbourList : Stateful {
  static constexpr const char* key = "dem_neighbour_list";
  double skin = 0.1;
  bool reorder = false;         // put the spheres in cell order at each build
  bool keeps_history = false;   // carry shear (friction) through rebuilds
  // By rank m in cell order: sphere order[m]'s pairs are p in
  // [offsets[m], offsets[m + 1]), with partner list[p] (a sphere index).
  std::vector<std::uint32_t> order;
  std::vector<std::uint32_t> rank;     // of each sphere
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> list;
  std::vector<std::uint32_t> first;    // per pair: its first sphere, order[m] above
  std::vector<std::uint32_t> slabs;    // slab s holds ranks [slabs[s], slabs[s + 1])
  bool periodic_slabs = false;         // the first slab's pairs reach into the last
  std::vector<Vec<D>> reference;       // positions at the last build
  std::vector<Shear> shear;            // per pair (when keeps_history)
  std::vector<Shear> wall_shear;       // per sphere and wall: wall_shear[i * walls + w]
  ThreadDomains domains;               // whole slabs per thread, from the lists
  // The largest squared displacement since the build, as the drift of step
  // displacement_step measured it (the list's own test is then not needed).
  double displacement_squared = 0.0;
  std::int64_t displacement_step = -1;
  std::size_t walls = 0;
  std::uint64_t builds = 0;
  // Set where the lists are one rank's part of a system spread over ranks,
  // lent for a checkpoint written by rank (dem_domain_step.hpp): the rank's
  // own spheres in the whole system's numbering (order: their whole
  // indices; list: their partners'), and the whole system's slabs. A
  // checkpoint's rows, not lists to step with.
  bool part_of_whole = false;

  bool built() const { return !offsets.empty(); }
  // No lists, and their memory given back (the settings and the build count stay).
  void release() {
    for (auto* v : {&order, &rank, &offsets, &list, &first, &slabs}) std::vector<std::uint32_t>().swap(*v);
    std::vector<Vec<D>>().swap(reference);
    std::vector<Shear>().swap(shear);
    std::vector<Shear>().swap(wall_shear);
    domains = {};
    part_of_whole = false;
  }
  // Sphere i's pairs.
  std::pair<std::uint32_t, std::uint32_t> pairs_of(std::size_t i) const { return {offsets[rank[i]], offsets[rank[i] + 1]}; }

  // Per sphere in cell order its pair count rather than the offsets, so
  // that the ranks' rows of a part_of_whole follow one another. The arrays
  // of a row per sphere or per pair are named rows/..., which a checkpoint
  // read over ranks leaves in the file (holds_particle_rows) for each rank
  // to read its part (resumed_part.hpp).
  StateMap save_state() const override {
    StateMap s;
    s["rows/order"].assign(order.begin(), order.end());
    auto& counts = s["rows/pair_counts"];
    counts.resize(order.size());
    for (std::size_t m = 0; m < order.size(); ++m) counts[m] = offsets[m + 1] - offsets[m];
    s["rows/list"].assign(list.begin(), list.end());
    s["slabs"].assign(slabs.begin(), slabs.end());
    s["periodic_slabs"] = {periodic_slabs ? 1.0 : 0.0};
    s["rows/reference"] = flatten_vectors(reference);
    s["rows/shear"] = flatten_shears(shear);
    s["rows/wall_shear"] = flatten_shears(wall_shear);
    s["builds"] = {static_cast<double>(builds)};
    return s;
  }
  std::map<std::string, std::size_t> state_rows() const override {
    if (!part_of_whole) return {};
    const std::size_t spheres = order.size(), pairs = list.size();
    return {{"rows/order", spheres}, {"rows/pair_counts", spheres}, {"rows/reference", spheres},
            {"rows/wall_shear", spheres}, {"rows/list", pairs}, {"rows/shear", pairs}};
  }
  // A state without the rows (a run resumed by part over ranks, which
  // reads its part of them itself) restores the slabs and the build count
  // and leaves the lists unbuilt. Reads the names written before the rows
  // were named so, too.
  void restore_state(const StateMap& s) override {
    const auto named = [&](const std::string& name) -> const std::vector<double>* {
      for (const std::string& key : {"rows/" + name, name})
        if (const auto found = s.find(key); found != s.end()) return &found->second;
      return nullptr;
    };
    const auto indices = [&](const std::vector<double>& in, std::vector<std::uint32_t>& out) {
      out.assign(in.size(), 0);
      for (std::size_t k = 0; k < in.size(); ++k) out[k] = static_cast<std::uint32_t>(in[k]);
    };
    const auto at = [&](const std::string& name) -> const std::vector<double>& {
      if (const auto* values = named(name)) return *values;
      throw std::invalid_argument("checkpoint neighbour lists lack '" + name + "'");
    };
    release();
    indices(at("slabs"), slabs);
    periodic_slabs = at("periodic_slabs").at(0) != 0.0;
    builds = static_cast<std::uint64_t>(at("builds").at(0));
    displacement_step = -1;
    if (!named("order")) return;
    indices(at("order"), order);
    if (const auto* counts = named("pair_counts")) {
      if (counts->size() != order.size()) throw std::invalid_argument("checkpoint neighbour lists are inconsistent");
      offsets.assign(order.size() + 1, 0);
      for (std::size_t m = 0; m < order.size(); ++m)
        offsets[m + 1] = offsets[m] + static_cast<std::uint32_t>((*counts)[m]);
    } else {
      indices(at("offsets"), offsets);
    }
    indices(at("list"), list);
    reference.resize(order.size());
    unflatten_vectors(at("reference"), reference, "neighbour-list reference positions");
    unflatten_shears(at("shear"), shear);
    unflatten_shears(at("wall_shear"), wall_shear);
    if (offsets.size() != order.size() + 1 || list.size() != offsets.back() || slabs.empty() ||
        slabs.back() != order.size())
      throw std::invalid_argument("checkpoint neighbour lists are inconsistent");
    derive();
  }
  static std::vector<double> flatten_shears(const std::vector<Shear>& shears) {
    std::vector<double> out;
    out.reserve(3 * shears.size());
    for (const Shear& h : shears) out.insert(out.end(), h.begin(), h.end());
    return out;
  }
  static void unflatten_shears(const std::vector<double>& in, std::vector<Shear>& out) {
    if (in.size() % 3) throw std::invalid_argument("checkpoint shear history has the wrong size");
    out.assign(in.size() / 3, Shear{});
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = {in[3 * k], in[3 * k + 1], in[3 * k + 2]};
  }
  // rank, first and the domains, from order, offsets and slabs.
  void derive() {
    rank.resize(order.size());
    first.resize(list.size());
    for (std::size_t m = 0; m < order.size(); ++m) {
      rank[order[m]] = static_cast<std::uint32_t>(m);
      std::fill(first.begin() + offsets[m], first.begin() + offsets[m + 1], order[m]);
    }
    domains = balanced_domains(slabs, offsets, domain_threads());
  }
};

// The domains of a per-sphere pass: those of the lists once built (spheres
// of ranks, which are their indices when they are kept in cell order),
// equal runs of indices before.
template <int D>
ThreadDomains sphere_domains(const View<Reads<NeighbourList<D>>, Writes<>>& view) {
  const std::size_t threads = domain_threads();
  if (view.template has<NeighbourList<D>>()) {
    const auto& nl = view.template read<NeighbourList<D>>();
    if (nl.domains.covers(view.size()) && nl.domains.count() == threads) return nl.domains;
  }
  return even_domains(view.size(), threads);
}

// The largest squared displacement of the spheres [from, to) since the
// last build (a wrapped sphere is its own periodic image: the nearest one
// counts).
template <int D>
double largest_displacement_squared(const Vec<D>* x, const NeighbourList<D>& nl, const Box<D>& box, std::size_t from,
                                    std::size_t to) {
  const std::array<double, D> half = box.half_periods();
  double most = 0.0;
  for (std::size_t i = from; i < to; ++i) {
    double d2 = 0.0;
    for (int k = 0; k < D; ++k) {
      const double e = nearest_image(x[i][k] - nl.reference[i][k], box.length[k], half[k]);
      d2 += e * e;
    }
    // A position that is not finite counts as the largest move: it forces
    // a build, where the watchdog finds it.
    most = d2 < most ? most : d2;
  }
  return most;
}

// largest = max(largest, value), from any thread: a maximum is the same
// whichever gets there first. NaN wins, as above.
inline void raise_to(std::atomic<double>& largest, double value) {
  double seen = largest.load(std::memory_order_relaxed);
  while (!(value <= seen) && !std::isnan(seen) &&
         !largest.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
  }
}

// The partners of every sphere into nl.offsets, nl.list and nl.first: of
// the sphere of rank m (ranks in cell order; `sorted` holds their position
// and radius, `sorted_cell` their cell, `start` where each cell's ranks
// begin), the spheres later in cell order within reach.
template <int D>
void list_partners(const CellGrid<D>& grid, const std::vector<std::uint32_t>& start,
                   const std::vector<std::uint32_t>& sorted_cell, const std::vector<std::array<double, D + 1>>& sorted,
                   const Box<D>& box, NeighbourList<D>& nl) {
  const std::size_t n = sorted.size();
  const std::array<double, D> half = box.half_periods();
  const double skin = nl.skin;
  // The partners of the sphere of rank m: the spheres later in cell order
  // within reach. Only cells at or after its own hold them: a pair of
  // neighbouring cells is searched from the earlier one, the pairs of one
  // cell by rank.
  const auto visit = [&](std::uint32_t m, std::vector<std::uint32_t>& out) {
    const std::size_t home = sorted_cell[m];
    // The candidate ranges of ranks: the cells at or after home, within home after m.
    std::array<std::array<std::uint32_t, 2>, 27> ranges{};
    int count_ranges = 0;
    std::size_t candidates = 0;
    grid.for_each_neighbour(home, [&](std::size_t c) {
      if (c < home) return;
      const std::uint32_t begin = c == home ? m + 1 : start[c], end = start[c + 1];
      if (end <= begin) return;
      ranges[count_ranges++] = {begin, end};
      candidates += end - begin;
    });
    std::size_t filled = out.size();
    out.resize(filled + candidates);
    std::uint32_t* const slot = out.data();
    const auto& me = sorted[m];
    for (int r = 0; r < count_ranges; ++r)
      for (std::uint32_t q = ranges[r][0]; q < ranges[r][1]; ++q) {
        const auto& other = sorted[q];
        double d2 = 0.0;
        for (int k = 0; k < D; ++k) {
          const double d = nearest_image(me[k] - other[k], box.length[k], half[k]);
          d2 += d * d;
        }
        const double reach = me[D] + other[D] + skin;
        slot[filled] = nl.order[q];
        filled += d2 < reach * reach;
      }
    out.resize(filled);
  };
  // One pass: each fixed chunk of ranks lists its partners in its own
  // buffer; the chunks are then joined in order (the same list on any
  // thread count).
  constexpr std::size_t chunk = 256;
  const std::size_t chunks = (n + chunk - 1) / chunk;
  std::vector<std::vector<std::uint32_t>> pieces(chunks);
  nl.offsets.assign(n + 1, 0);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t q) {
    auto& piece = pieces[q];
    piece.reserve(8 * chunk);
    const std::size_t end = std::min(n, (q + 1) * chunk);
    for (std::size_t m = q * chunk; m < end; ++m) {
      const std::size_t before = piece.size();
      visit(static_cast<std::uint32_t>(m), piece);
      nl.offsets[m + 1] = static_cast<std::uint32_t>(piece.size() - before);
    }
  });
  for (std::size_t m = 0; m < n; ++m) nl.offsets[m + 1] += nl.offsets[m];
  nl.list.resize(nl.offsets[n]);
  nl.first.resize(nl.offsets[n]);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t q) {
    std::copy(pieces[q].begin(), pieces[q].end(), nl.list.begin() + nl.offsets[q * chunk]);
    const std::size_t end = std::min(n, (q + 1) * chunk);
    for (std::size_t m = q * chunk; m < end; ++m)
      std::fill(nl.first.begin() + nl.offsets[m], nl.first.begin() + nl.offsets[m + 1], nl.order[m]);
  });
}

// The cells of a build: at least one interaction range wide; wider where a
// box much larger than the spheres need (a tall, empty box, tiny spheres)
// would otherwise ask for more cells than memory holds (wider cells only
// list more candidates). A periodic axis of fewer than three cells would
// meet the same neighbour from both sides: it gets one.
template <int D>
CellGrid<D> list_cells(const Box<D>& box, double range, std::size_t spheres) {
  std::array<double, D> wanted{};
  double total = 1.0;
  for (int k = 0; k < D; ++k) {
    wanted[k] = std::max(1.0, std::floor(box.length[k] / range));
    total *= wanted[k];
  }
  const double most = std::max(8.0 * static_cast<double>(spheres), 65536.0);
  const double shrink = total > most ? std::pow(most / total, 1.0 / D) : 1.0;
  std::array<int, D> cells{};
  for (int k = 0; k < D; ++k) {
    cells[k] = static_cast<int>(std::clamp(std::floor(wanted[k] * shrink), 1.0, most));
    if (box.periodic[k] && cells[k] < 3) cells[k] = 1;
  }
  return CellGrid<D>({}, box.length, cells, box.periodic);
}

// The spring a pair (a, b) of a new build takes from the last one, where
// find(a, b, h) gives the spring of (a, b) as listed under a: that one, or
// the one listed under b negated (the two swapped order), or none.
template <class Find>
Shear carried_spring(std::uint32_t a, std::uint32_t b, const Find& find) {
  Shear h{};
  if (find(a, b, h)) return h;
  if (find(b, a, h)) {
    for (double& c : h) c = -c;
    return h;
  }
  return Shear{};
}

template <int D>
using DemNeighbourListBase = SystemOf<Reads<Clock, Radius, Box<D>, DemWatch<D>>,
                                      Writes<Position<D>, NeighbourList<D>, RunControl, EveryColumn>>;

// A build may reorder the spheres (World::permute), which moves every column.
template <int D>
class DemNeighbourList : public DemNeighbourListBase<D> {
 public:
  using View = typename DemNeighbourListBase<D>::View;
  std::string name() const override { return "dem_neighbour_list"; }

  void run_on(View view) override {
    auto& nl = view.template write<NeighbourList<D>>();
    if (!nl.built() || moved_too_far(view, nl)) build(view, nl);
  }

  // Whether some sphere moved more than half the skin since the last build:
  // the drift's figure of this step where it gave one, else measured here.
  static bool moved_too_far(const granflow::View<Reads<Clock, Position<D>, Box<D>, NeighbourList<D>>, Writes<>>& view,
                            const NeighbourList<D>& nl) {
    const double limit = 0.25 * nl.skin * nl.skin;
    if (nl.displacement_step == view.template read<Clock>().step) return !(nl.displacement_squared <= limit);
    const auto& x = view.template read<Position<D>>();
    const auto& box = view.template read<Box<D>>();
    std::atomic<double> largest{0.0};
    for_each_sphere_run(sphere_domains<D>(view), [&](std::size_t, std::size_t from, std::size_t to) {
      raise_to(largest, largest_displacement_squared(x.values.data(), nl, box, from, to));
    });
    return !(largest <= limit);
  }

  static void build(View view, NeighbourList<D>& nl) {
    const auto& box = view.template read<Box<D>>();
    const std::size_t n = view.size();
    const auto& radii = view.template read<Radius>();
    const double largest = n ? *std::max_element(radii.values.begin(), radii.values.end()) : 0.0;
    const CellGrid<D> grid = list_cells(box, 2.0 * largest + nl.skin, n);
    const std::size_t cell_count = grid.cell_count();
    // Counting sort of the spheres by cell; the same pass holds every
    // position to the walls' reach (dem_watchdog.hpp). A sphere through a
    // wall or not finite moves on (or is NaN) and so forces a build soon:
    // checked here, the watchdog costs the step nothing.
    std::vector<std::uint32_t> cell(n), start(cell_count + 1, 0), members(n);
    std::atomic<bool> escaped{false};
    {
      const auto& x = view.template read<Position<D>>();
      std::array<double, D> lower, upper;
      lower.fill(-std::numeric_limits<double>::infinity());
      upper.fill(std::numeric_limits<double>::infinity());
      if (view.template has<DemWatch<D>>()) {
        lower = view.template read<DemWatch<D>>().lower;
        upper = view.template read<DemWatch<D>>().upper;
      }
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
        bool inside = true;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          for (int k = 0; k < D; ++k) inside &= (x[i][k] >= lower[k]) & (x[i][k] <= upper[k]);  // false for NaN
          // A sphere far outside (the watchdog then stops the run) or not finite lands in an edge cell.
          cell[i] = static_cast<std::uint32_t>(grid.cell_of(x[i]));
        }
        if (!inside) escaped.store(true, std::memory_order_relaxed);
      });
    }
    std::vector<std::uint32_t> chunk_counts;
    count_scan_fill(cell.data(), n, cell_count, start.data(), members.data(), chunk_counts);
    // The previous lists, in the previous order, for the shear history.
    NeighbourList<D> previous;
    std::vector<std::uint32_t> was;  // was[new index] = index at the previous build's end
    if (nl.keeps_history && nl.built()) {
      previous.rank.swap(nl.rank);
      previous.offsets.swap(nl.offsets);
      previous.list.swap(nl.list);
      previous.shear.swap(nl.shear);
      previous.wall_shear.swap(nl.wall_shear);
    }
    if (nl.reorder) {
      view.permute(members);
      was = members;
    }
    const auto& x = view.template read<Position<D>>();
    const auto& radius = view.template read<Radius>();
    // The spheres by rank: their index, position, radius and cell; the
    // candidates of a cell are then contiguous.
    nl.order.resize(n);
    nl.rank.resize(n);
    std::vector<std::uint32_t> sorted_cell(n);
    std::vector<std::array<double, D + 1>> sorted(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
      for (std::size_t m = r.begin(); m != r.end(); ++m) {
        const std::uint32_t i = nl.reorder ? static_cast<std::uint32_t>(m) : members[m];
        nl.order[m] = i;
        nl.rank[i] = static_cast<std::uint32_t>(m);
        sorted_cell[m] = cell[was.empty() ? i : was[m]];
        for (int k = 0; k < D; ++k) sorted[m][k] = x[i][k];
        sorted[m][D] = radius[i];
      }
    });
    // One slab per layer of cells along the last axis.
    const auto layers = static_cast<std::size_t>(grid.cells(D - 1));
    nl.slabs.resize(layers + 1);
    for (std::size_t s = 0; s <= layers; ++s) nl.slabs[s] = start[s * grid.stride(D - 1)];
    nl.periodic_slabs = box.periodic[D - 1] && layers > 1;
    list_partners(grid, start, sorted_cell, sorted, box, nl);
    if (nl.keeps_history) carry_history(nl, previous, was, n);
    nl.domains = balanced_domains(nl.slabs, nl.offsets, domain_threads());
    nl.reference.assign(x.values.begin(), x.values.end());
    ++nl.builds;
    if (escaped) report_escaped_sphere<D>(view);
  }

 private:
  // Each new pair takes the shear of the same two spheres in the previous
  // lists (negated where their order swapped), each sphere its wall shears.
  static void carry_history(NeighbourList<D>& nl, const NeighbourList<D>& previous, const std::vector<std::uint32_t>& was,
                            std::size_t n) {
    nl.shear.assign(nl.list.size(), Shear{});
    nl.wall_shear.assign(n * nl.walls, Shear{});
    if (!previous.built()) return;
    const auto old_index = [&](std::size_t i) { return was.empty() ? static_cast<std::uint32_t>(i) : was[i]; };
    // The pair (a, b) was listed under a or under b; its shear is that of
    // its first sphere.
    const auto find = [&](std::uint32_t a, std::uint32_t b, Shear& h) {
      const auto [begin, end] = previous.pairs_of(a);
      for (std::uint32_t q = begin; q < end; ++q)
        if (previous.list[q] == b) {
          h = previous.shear[q];
          return true;
        }
      return false;
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 512), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const std::uint32_t a = old_index(i);
        for (std::size_t w = 0; w < nl.walls; ++w) nl.wall_shear[i * nl.walls + w] = previous.wall_shear[a * nl.walls + w];
        const auto [begin, end] = nl.pairs_of(i);
        for (std::uint32_t p = begin; p < end; ++p) nl.shear[p] = carried_spring(a, old_index(nl.list[p]), find);
      }
    });
  }
};

}  // namespace granflow::dem
