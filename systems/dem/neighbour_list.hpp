#pragma once
// Verlet neighbour lists of soft spheres (a World resource and the system
// that keeps it). Half lists: sphere i lists the spheres after it in cell
// order whose surfaces are within the skin, so each pair is evaluated once;
// the reverse lists name, for each sphere, the pairs in which it is the
// second member, so the force pass can gather every sphere's forces without
// atomics and in the same order on any thread count. The lists are rebuilt
// from a cell grid (cells at least one interaction range wide, a counting
// sort, the 3^D neighbouring cells) only when some sphere has moved more
// than half the skin since the last build: then no pair can have come into
// contact unlisted. Rebuilds are counted. At a rebuild the spheres can be
// put in cell order (World::permute, `reorder`): neighbours then sit close
// in memory, and a sphere's partners all have larger indices. The
// tangential-spring history of each contact follows its pair through
// rebuilds and reorderings.

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "components/position.hpp"
#include "components/radius.hpp"
#include "engine/state_map.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"
#include "systems/dem/nearest_image.hpp"

namespace granflow::dem {

inline const SystemDescription dem_neighbour_list_description{
    "dem_neighbour_list",
    "half Verlet lists with a skin from a cell grid, rebuilt (spheres put in cell order) when one moved half the skin"};

// The box: edge lengths from 0, and which axes are periodic (the others end at walls).
template <int D>
struct DemBox {
  static constexpr const char* key = "dem_box";
  std::array<double, D> length{};
  std::array<bool, D> periodic{};

  // Puts p back into the box along the periodic axes; returns what was
  // subtracted (for what moves with p, such as its previous position).
  Vec<D> wrap(Vec<D>& p) const {
    Vec<D> shift = Vec<D>::Zero();
    for (int k = 0; k < D; ++k)
      // Most steps leave a sphere inside: the division only where it left.
      if (periodic[k] && (p[k] < 0.0 || p[k] >= length[k])) {
        shift[k] = length[k] * std::floor(p[k] / length[k]);
        p[k] -= shift[k];
      }
    return shift;
  }

  // Half the box length along the periodic axes, infinity along the others:
  // a separation beyond it is wrapped by nearest_image.
  std::array<double, D> half_periods() const {
    std::array<double, D> half{};
    for (int k = 0; k < D; ++k) half[k] = periodic[k] ? 0.5 * length[k] : std::numeric_limits<double>::infinity();
    return half;
  }

  // The separation a - b, as the minimal image along periodic axes.
  void separation(const Vec<D>& a, const Vec<D>& b, double* out) const {
    for (int k = 0; k < D; ++k) {
      double d = a[k] - b[k];
      if (periodic[k]) {
        if (d > 0.5 * length[k]) d -= length[k];
        else if (d < -0.5 * length[k]) d += length[k];
      }
      out[k] = d;
    }
  }
};

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
  std::vector<std::uint32_t> offsets;  // sphere i's pairs: p in [offsets[i], offsets[i + 1]), partner list[p]
  std::vector<std::uint32_t> list;
  std::vector<std::uint32_t> first;    // per pair: its first sphere (i above), for loops over all pairs
  std::vector<std::uint32_t> reverse_offsets;  // sphere j's pairs as the second member: reverse[..] in
  std::vector<std::uint32_t> reverse;          // [reverse_offsets[j], reverse_offsets[j + 1]), increasing
  std::vector<Vec<D>> reference;               // positions at the last build
  std::vector<Shear> shear;                    // per pair (when keeps_history)
  std::vector<Shear> wall_shear;               // per sphere and wall: wall_shear[i * walls + w]
  std::size_t walls = 0;
  std::uint64_t builds = 0;

  bool built() const { return !offsets.empty(); }

  StateMap save_state() const override {
    StateMap s;
    s["offsets"].assign(offsets.begin(), offsets.end());
    s["list"].assign(list.begin(), list.end());
    s["reverse_offsets"].assign(reverse_offsets.begin(), reverse_offsets.end());
    s["reverse"].assign(reverse.begin(), reverse.end());
    s["reference"] = flatten_vectors(reference);
    for (const char* name : {"shear", "wall_shear"}) {
      const auto& from = name[0] == 's' ? shear : wall_shear;
      auto& to = s[name];
      for (const Shear& h : from) to.insert(to.end(), h.begin(), h.end());
    }
    s["builds"] = {static_cast<double>(builds)};
    return s;
  }
  void restore_state(const StateMap& s) override {
    const auto indices = [&](const char* name, std::vector<std::uint32_t>& out) {
      const auto& in = s.at(name);
      out.assign(in.size(), 0);
      for (std::size_t k = 0; k < in.size(); ++k) out[k] = static_cast<std::uint32_t>(in[k]);
    };
    indices("offsets", offsets);
    indices("list", list);
    indices("reverse_offsets", reverse_offsets);
    indices("reverse", reverse);
    reference.resize(offsets.empty() ? 0 : offsets.size() - 1);
    unflatten_vectors(s.at("reference"), reference, "neighbour-list reference positions");
    for (const char* name : {"shear", "wall_shear"}) {
      const auto& in = s.at(name);
      if (in.size() % 3) throw std::invalid_argument("checkpoint shear history has the wrong size");
      auto& to = name[0] == 's' ? shear : wall_shear;
      to.assign(in.size() / 3, Shear{});
      for (std::size_t k = 0; k < to.size(); ++k) to[k] = {in[3 * k], in[3 * k + 1], in[3 * k + 2]};
    }
    builds = static_cast<std::uint64_t>(s.at("builds").at(0));
    if (offsets.size() != reference.size() + 1 || list.size() != offsets.back() || reverse.size() != list.size())
      throw std::invalid_argument("checkpoint neighbour lists are inconsistent");
    first.resize(list.size());
    for (std::size_t i = 0; i + 1 < offsets.size(); ++i)
      std::fill(first.begin() + offsets[i], first.begin() + offsets[i + 1], static_cast<std::uint32_t>(i));
  }
};

template <int D>
class DemNeighbourList : public System {
 public:
  std::string name() const override { return "dem_neighbour_list"; }
  Access access() const override {
    // A build may reorder every column (World::permute).
    return Access{}.reads<Radius, DemBox<D>>().template writes<Position<D>, NeighbourList<D>>().writes_every_component();
  }

  void run(World& world) override {
    auto& nl = world.resource<NeighbourList<D>>();
    if (!nl.built() || moved_too_far(world, nl)) build(world, nl);
  }

  // Whether some sphere moved more than half the skin since the last build
  // (a maximum: the same on any split over threads).
  static bool moved_too_far(const World& world, const NeighbourList<D>& nl) {
    const auto& x = world.component<Position<D>>();
    const auto& box = world.resource<DemBox<D>>();
    const std::array<double, D> half = box.half_periods();
    const double largest = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, world.size(), 4096), 0.0,
        [&](const auto& range, double worst) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            double d2 = 0.0;
            for (int k = 0; k < D; ++k) {
              // A wrapped sphere is its own periodic image: the nearest one counts.
              const double d = nearest_image(x[i][k] - nl.reference[i][k], box.length[k], half[k]);
              d2 += d * d;
            }
            worst = std::max(worst, d2);
          }
          return worst;
        },
        [](double a, double b) { return std::max(a, b); });
    return largest > 0.25 * nl.skin * nl.skin;
  }

  static void build(World& world, NeighbourList<D>& nl) {
    const auto& box = world.resource<DemBox<D>>();
    const std::size_t n = world.size();
    const auto& radii = world.component<Radius>();
    const double largest = n ? *std::max_element(radii.values.begin(), radii.values.end()) : 0.0;
    const double range = 2.0 * largest + nl.skin;
    std::array<int, D> cells{};
    std::array<std::size_t, D> stride{};
    std::array<double, D> per_length{};
    std::size_t cell_count = 1;
    for (int k = 0; k < D; ++k) {
      cells[k] = std::max(1, static_cast<int>(std::floor(box.length[k] / range)));
      // A periodic axis of fewer than three cells would list an image twice.
      if (box.periodic[k] && cells[k] < 3) cells[k] = 1;
      stride[k] = cell_count;
      per_length[k] = cells[k] / box.length[k];
      cell_count *= static_cast<std::size_t>(cells[k]);
    }
    // Counting sort of the spheres by cell.
    std::vector<std::uint32_t> cell(n), start(cell_count + 1, 0), members(n);
    {
      const auto& x = world.component<Position<D>>();
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          std::size_t c = 0;
          for (int k = 0; k < D; ++k) {
            const int q = std::clamp(static_cast<int>(std::floor(x[i][k] * per_length[k])), 0, cells[k] - 1);
            c += stride[k] * static_cast<std::size_t>(q);
          }
          cell[i] = static_cast<std::uint32_t>(c);
        }
      });
    }
    for (std::size_t i = 0; i < n; ++i) ++start[cell[i] + 1];
    for (std::size_t c = 0; c < cell_count; ++c) start[c + 1] += start[c];
    {
      std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
      for (std::size_t i = 0; i < n; ++i) members[next[cell[i]]++] = static_cast<std::uint32_t>(i);
    }
    // The previous lists, in the previous order, for the shear history.
    NeighbourList<D> previous;
    std::vector<std::uint32_t> was;  // was[new index] = index at the previous build's end
    if (nl.keeps_history && nl.built()) {
      previous.offsets.swap(nl.offsets);
      previous.list.swap(nl.list);
      previous.shear.swap(nl.shear);
      previous.wall_shear.swap(nl.wall_shear);
    }
    if (nl.reorder) {
      world.permute(members);
      was = members;
    }
    const auto& x = world.component<Position<D>>();
    const auto& radius = world.component<Radius>();
    // The spheres' rank in cell order, and their positions, radii and cells
    // by rank: the candidates of a cell are then contiguous.
    std::vector<std::uint32_t> rank(n), sorted_cell(n);
    std::vector<std::array<double, D + 1>> sorted(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& r) {
      for (std::size_t m = r.begin(); m != r.end(); ++m) {
        const std::uint32_t i = nl.reorder ? static_cast<std::uint32_t>(m) : members[m];
        if (nl.reorder) members[m] = i;
        rank[i] = static_cast<std::uint32_t>(m);
        sorted_cell[m] = cell[was.empty() ? i : was[m]];
        for (int k = 0; k < D; ++k) sorted[m][k] = x[i][k];
        sorted[m][D] = radius[i];
      }
    });
    const std::array<double, D> half = box.half_periods();
    const double skin = nl.skin;
    // Sphere i's partners: the spheres later in cell order within reach.
    // Only cells at or after its own hold them: a pair of neighbouring cells
    // is searched from the earlier one, the pairs of one cell by rank.
    const auto visit = [&](std::size_t i, std::vector<std::uint32_t>& out) {
      const std::uint32_t m = rank[i];
      const std::size_t home = sorted_cell[m];
      // Along each axis the (at most three) neighbouring cell coordinates, as index terms.
      std::array<std::array<std::size_t, 3>, D> term{};
      std::array<int, D> count{};
      for (int k = 0; k < D; ++k) {
        const int h = static_cast<int>(home / stride[k] % static_cast<std::size_t>(cells[k]));
        for (int o = -1; o <= 1; ++o) {
          int q = h + o;
          if (cells[k] == 1 && o != 0) continue;  // one cell along k: visited once
          if (box.periodic[k]) q = (q + cells[k]) % cells[k];
          else if (q < 0 || q >= cells[k]) continue;
          term[k][count[k]++] = stride[k] * static_cast<std::size_t>(q);
        }
      }
      // The candidate ranges of ranks: the cells at or after home, within home after m.
      std::array<std::array<std::uint32_t, 2>, 27> ranges{};
      int count_ranges = 0;
      std::size_t candidates = 0;
      const auto take = [&](std::size_t c) {
        if (c < home) return;
        const std::uint32_t begin = c == home ? m + 1 : start[c], end = start[c + 1];
        if (end <= begin) return;
        ranges[count_ranges++] = {begin, end};
        candidates += end - begin;
      };
      if constexpr (D == 2) {
        for (int b = 0; b < count[1]; ++b)
          for (int a = 0; a < count[0]; ++a) take(term[1][b] + term[0][a]);
      } else {
        for (int e = 0; e < count[2]; ++e)
          for (int b = 0; b < count[1]; ++b)
            for (int a = 0; a < count[0]; ++a) take(term[2][e] + term[1][b] + term[0][a]);
      }
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
          slot[filled] = members[q];
          filled += d2 < reach * reach;
        }
      out.resize(filled);
    };
    // One pass: each fixed chunk of spheres lists its partners in its own
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
      for (std::size_t i = q * chunk; i < end; ++i) {
        const std::size_t before = piece.size();
        visit(i, piece);
        nl.offsets[i + 1] = static_cast<std::uint32_t>(piece.size() - before);
      }
    });
    for (std::size_t i = 0; i < n; ++i) nl.offsets[i + 1] += nl.offsets[i];
    nl.list.resize(nl.offsets[n]);
    nl.first.resize(nl.offsets[n]);
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t q) {
      std::copy(pieces[q].begin(), pieces[q].end(), nl.list.begin() + nl.offsets[q * chunk]);
      const std::size_t end = std::min(n, (q + 1) * chunk);
      for (std::size_t i = q * chunk; i < end; ++i)
        std::fill(nl.first.begin() + nl.offsets[i], nl.first.begin() + nl.offsets[i + 1], static_cast<std::uint32_t>(i));
    });
    build_reverse(nl, n);
    if (nl.keeps_history) carry_history(nl, previous, was, n);
    nl.reference.assign(x.values.begin(), x.values.end());
    ++nl.builds;
  }

  // The reverse lists: a counting sort of the pairs by their second member.
  static void build_reverse(NeighbourList<D>& nl, std::size_t n) {
    nl.reverse_offsets.assign(n + 1, 0);
    for (std::uint32_t j : nl.list) ++nl.reverse_offsets[j + 1];
    for (std::size_t j = 0; j < n; ++j) nl.reverse_offsets[j + 1] += nl.reverse_offsets[j];
    nl.reverse.resize(nl.list.size());
    std::vector<std::uint32_t> next(nl.reverse_offsets.begin(), nl.reverse_offsets.end() - 1);
    for (std::uint32_t p = 0; p < nl.list.size(); ++p) nl.reverse[next[nl.list[p]]++] = p;
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
      for (std::uint32_t q = previous.offsets[a]; q < previous.offsets[a + 1]; ++q)
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
        for (std::uint32_t p = nl.offsets[i]; p < nl.offsets[i + 1]; ++p) {
          const std::uint32_t b = old_index(nl.list[p]);
          Shear h{};
          if (find(a, b, h)) {
            nl.shear[p] = h;
          } else if (find(b, a, h)) {
            for (double& c : h) c = -c;
            nl.shear[p] = h;
          }
        }
      }
    });
  }
};

}  // namespace granflow::dem
