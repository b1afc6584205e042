#pragma once
// Verlet neighbour lists of soft spheres (a World resource and the system
// that keeps it). Half lists: sphere i lists the spheres j > i whose
// surfaces are within the skin, so each pair is evaluated once; the
// reverse lists name, for each sphere, the pairs in which it is the second
// member, so the force pass can gather every sphere's forces without
// atomics and in the same order on any thread count. The lists are rebuilt
// from a cell grid (cells at least one interaction range wide, a counting
// sort, the 3^D neighbouring cells) only when some sphere has moved more
// than half the skin since the last build: then no pair can have come into
// contact unlisted. Rebuilds are counted. At a rebuild the spheres can be
// put in cell order (World::permute, `reorder`): neighbours then sit close
// in memory. The tangential-spring history of each contact follows its pair
// through rebuilds and reorderings.

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "components/position.hpp"
#include "components/radius.hpp"
#include "engine/state_map.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"

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
  std::vector<std::uint32_t> offsets;  // sphere i's pairs: p in [offsets[i], offsets[i + 1]), partner list[p] > i
  std::vector<std::uint32_t> list;
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
    const double largest = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, world.size(), 4096), 0.0,
        [&](const auto& range, double worst) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            double d[D], d2 = 0.0;
            box.separation(x[i], nl.reference[i], d);
            for (int k = 0; k < D; ++k) d2 += d[k] * d[k];
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
    std::size_t cell_count = 1;
    for (int k = 0; k < D; ++k) {
      cells[k] = std::max(1, static_cast<int>(std::floor(box.length[k] / range)));
      // A periodic axis of fewer than three cells would list an image twice.
      if (box.periodic[k] && cells[k] < 3) cells[k] = 1;
      cell_count *= static_cast<std::size_t>(cells[k]);
    }
    const auto cell_of = [&](const Vec<D>& p, std::array<int, D>& index) {
      std::size_t c = 0, stride = 1;
      for (int k = 0; k < D; ++k) {
        int q = static_cast<int>(std::floor(p[k] / box.length[k] * cells[k]));
        q = std::clamp(q, 0, cells[k] - 1);
        index[k] = q;
        c += stride * static_cast<std::size_t>(q);
        stride *= static_cast<std::size_t>(cells[k]);
      }
      return c;
    };
    // Counting sort of the spheres by cell.
    std::vector<std::uint32_t> start(cell_count + 1, 0), members(n), cell(n);
    {
      const auto& x = world.component<Position<D>>();
      std::array<int, D> index{};
      for (std::size_t i = 0; i < n; ++i) {
        cell[i] = static_cast<std::uint32_t>(cell_of(x[i], index));
        ++start[cell[i] + 1];
      }
    }
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
      for (std::size_t k = 0; k < n; ++k) members[k] = static_cast<std::uint32_t>(k);
    }
    const auto& x = world.component<Position<D>>();
    const auto& radius = world.component<Radius>();
    // Sphere i's partners j > i, cell by cell of its neighbourhood.
    const auto visit = [&](std::size_t i, auto&& take) {
      std::array<int, D> home{};
      cell_of(x[i], home);
      std::array<int, D> offset{};
      for (int k = 0; k < D; ++k) offset[k] = -1;
      while (true) {
        std::size_t c = 0, stride = 1;
        bool inside = true;
        for (int k = 0; k < D; ++k) {
          int q = home[k] + offset[k];
          if (cells[k] == 1 && offset[k] != 0) inside = false;  // one cell along k: visited once
          if (box.periodic[k]) q = (q + cells[k]) % cells[k];
          else if (q < 0 || q >= cells[k]) inside = false;
          c += stride * static_cast<std::size_t>(std::max(q, 0));
          stride *= static_cast<std::size_t>(cells[k]);
        }
        if (inside)
          for (std::uint32_t m = start[c]; m < start[c + 1]; ++m) {
            const std::uint32_t j = members[m];
            if (j <= i) continue;
            double d[D], d2 = 0.0;
            box.separation(x[i], x[j], d);
            for (int k = 0; k < D; ++k) d2 += d[k] * d[k];
            const double reach = radius[i] + radius[j] + nl.skin;
            if (d2 < reach * reach) take(j);
          }
        int k = 0;
        while (k < D && ++offset[k] > 1) offset[k++] = -1;
        if (k == D) break;
      }
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
      const std::size_t end = std::min(n, (q + 1) * chunk);
      for (std::size_t i = q * chunk; i < end; ++i) {
        const std::size_t before = piece.size();
        visit(i, [&](std::uint32_t j) { piece.push_back(j); });
        nl.offsets[i + 1] = static_cast<std::uint32_t>(piece.size() - before);
      }
    });
    for (std::size_t i = 0; i < n; ++i) nl.offsets[i + 1] += nl.offsets[i];
    nl.list.resize(nl.offsets[n]);
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t q) {
      std::copy(pieces[q].begin(), pieces[q].end(), nl.list.begin() + nl.offsets[q * chunk]);
    });
    // The reverse lists: a counting sort of the pairs by their second member.
    nl.reverse_offsets.assign(n + 1, 0);
    for (std::uint32_t j : nl.list) ++nl.reverse_offsets[j + 1];
    for (std::size_t j = 0; j < n; ++j) nl.reverse_offsets[j + 1] += nl.reverse_offsets[j];
    nl.reverse.resize(nl.list.size());
    {
      std::vector<std::uint32_t> next(nl.reverse_offsets.begin(), nl.reverse_offsets.end() - 1);
      for (std::size_t i = 0; i < n; ++i)
        for (std::uint32_t p = nl.offsets[i]; p < nl.offsets[i + 1]; ++p) nl.reverse[next[nl.list[p]]++] = p;
    }
    if (nl.keeps_history) carry_history(nl, previous, was, n);
    nl.reference.assign(x.values.begin(), x.values.end());
    ++nl.builds;
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
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 512), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const std::uint32_t a = old_index(i);
        for (std::size_t w = 0; w < nl.walls; ++w) nl.wall_shear[i * nl.walls + w] = previous.wall_shear[a * nl.walls + w];
        for (std::uint32_t p = nl.offsets[i]; p < nl.offsets[i + 1]; ++p) {
          const std::uint32_t b = old_index(nl.list[p]);
          const std::uint32_t first = std::min(a, b), second = std::max(a, b);
          for (std::uint32_t q = previous.offsets[first]; q < previous.offsets[first + 1]; ++q)
            if (previous.list[q] == second) {
              Shear h = previous.shear[q];
              if (first != a)
                for (double& c : h) c = -c;
              nl.shear[p] = h;
              break;
            }
        }
      }
    });
  }
};

}  // namespace granflow::dem
