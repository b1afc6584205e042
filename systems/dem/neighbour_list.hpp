#pragma once
// Verlet neighbour lists of soft spheres (a World resource and the system
// that keeps it): every sphere lists all others whose surfaces are within
// the skin (full lists: each sphere sums its own forces, so the force loop
// needs no atomics). The lists are rebuilt from a cell grid (cells at least
// one interaction range wide, a counting sort, the 3^D neighbouring cells)
// only when some sphere has moved more than half the skin since the last
// build: then no pair can have come into contact unlisted. Rebuilds are
// counted. Lists keep a fixed order (cells, then particles in index order),
// so forces are summed in the same order on any thread count.

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "components/position.hpp"
#include "components/radius.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"

namespace granflow::dem {

inline const SystemDescription dem_neighbour_list_description{
    "dem_neighbour_list", "Verlet lists with a skin from a cell grid, rebuilt when a sphere moved half the skin"};

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
      if (periodic[k]) {
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

template <int D>
struct NeighbourList {
  static constexpr const char* key = "dem_neighbour_list";
  double skin = 0.1;
  std::vector<std::uint32_t> offsets;  // sphere i's neighbours: list[offsets[i] .. offsets[i + 1])
  std::vector<std::uint32_t> list;
  std::vector<Vec<D>> reference;       // positions at the last build
  std::uint64_t builds = 0;

  bool built() const { return !offsets.empty(); }
};

template <int D>
class DemNeighbourList : public System {
 public:
  std::string name() const override { return "dem_neighbour_list"; }
  Access access() const override {
    return Access{}.reads<Position<D>, Radius, DemBox<D>>().template writes<NeighbourList<D>>();
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

  static void build(const World& world, NeighbourList<D>& nl) {
    const auto& x = world.component<Position<D>>();
    const auto& radius = world.component<Radius>();
    const auto& box = world.resource<DemBox<D>>();
    const std::size_t n = world.size();
    const double largest = n ? *std::max_element(radius.values.begin(), radius.values.end()) : 0.0;
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
    std::array<int, D> index{};
    for (std::size_t i = 0; i < n; ++i) {
      cell[i] = static_cast<std::uint32_t>(cell_of(x[i], index));
      ++start[cell[i] + 1];
    }
    for (std::size_t c = 0; c < cell_count; ++c) start[c + 1] += start[c];
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) members[next[cell[i]]++] = static_cast<std::uint32_t>(i);
    // Each sphere's neighbours, counted, then written.
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
            if (j == i) continue;
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
    // One pass: each fixed chunk of spheres lists its neighbours in its own
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
    nl.reference.assign(x.values.begin(), x.values.end());
    ++nl.builds;
  }
};

}  // namespace granflow::dem
