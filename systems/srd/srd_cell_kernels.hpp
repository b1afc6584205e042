#pragma once
// One cell's share of the SRD step, as functions the CPU systems and the
// CUDA kernels both call, so that the two back ends do the same arithmetic
// in the same order: the running sums of its particles (taken about the
// velocity of its first particle in storage order, so that a fast cell's
// sums do not cancel), its ghost particles, its mean velocity and
// temperature from those sums, and its collision operator.

#include <cstdint>

#include "engine/core/host_device.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "systems/srd/srd_kernels.hpp"
#include "systems/srd/srd_walls.hpp"

namespace granflow::srd {

// A cell's running sums in the reduction, together in one cache line.
template <int D>
struct alignas(64) CellSums {
  double reference[D];
  double sum[D];   // sum m (v - reference)
  double squares;  // sum m |v - reference|^2
  double mass;
};

// The first particle of a cell: its velocity (as the cell sees it) becomes the reference.
template <int D>
GRANFLOW_HD inline void start_sums(CellSums<D>& s, const double* seen) {
  for (int a = 0; a < D; ++a) {
    s.reference[a] = seen[a];
    s.sum[a] = 0.0;
  }
  s.squares = 0.0;
  s.mass = 0.0;
}

// Adds one particle of mass m; w: its velocity less the reference.
template <int D>
GRANFLOW_HD inline void add_to_sums(CellSums<D>& s, const double* seen, double m, double* w) {
  double w2 = 0.0;
  for (int a = 0; a < D; ++a) {
    w[a] = seen[a] - s.reference[a];
    w2 += w[a] * w[a];
  }
  s.mass += m;
  for (int a = 0; a < D; ++a) s.sum[a] += m * w[a];
  s.squares += m * w2;
}

// How many ghost particles fill a cell of `count` particles up to `fill`
// (none for an empty cell: it has nothing to rotate).
GRANFLOW_HD inline int ghost_count(std::uint32_t count, double fill) {
  if (count == 0) return 0;
  const auto missing = static_cast<int>(fill + 0.5) - static_cast<int>(count);
  return missing > 0 ? missing : 0;
}

// Adds `missing` ghost particles of mass `particle_mass` at the wall's
// temperature and velocity (Lamura et al. 2001), drawn as their sums keyed
// by (seed, step, cell): m n (mean - r) and m (scatter + n |mean - r|^2)
// about the reference r.
template <int D>
GRANFLOW_HD inline void add_ghosts_to_sums(CellSums<D>& s, int missing, const Wall& wall, double time,
                                           double particle_mass, std::uint64_t seed, std::uint64_t step,
                                           std::uint64_t c) {
  Philox random(stream::srd_ghosts, seed, step, c);
  const GhostSums ghosts = ghost_sums<D>(missing, wall, time, particle_mass, random);
  const double m = particle_mass * missing;
  double offset2 = 0.0;
  for (int b = 0; b < D; ++b) {
    const double offset = ghosts.mean[b] - s.reference[b];
    s.sum[b] += m * offset;
    offset2 += offset * offset;
  }
  s.squares += particle_mass * ghosts.scatter + m * offset2;
  s.mass += m;
}

// The layer of this step's grid that a no-slip wall with ghosts cuts: the
// wall (its index), the stride of its axis in the linear cell index, and
// where along that axis it lies.
struct CutLayer {
  int wall;
  std::uint32_t stride;
  std::int64_t layer;
};

// The layers the walls cut at `time` on a grid of `cells` per axis whose
// cells start at origin - shift; at most one per wall, in wall order.
// Returns how many it wrote to `out`.
GRANFLOW_HD inline int find_cut_layers(const Wall* walls, int wall_count, const std::int32_t* cells,
                                       const double* shift, const double* origin, double time, CutLayer* out) {
  int found = 0;
  for (int w = 0; w < wall_count; ++w) {
    const Wall& wall = walls[w];
    if (wall.kind != WallKind::no_slip || !wall.ghosts) continue;
    std::uint32_t stride = 1;
    for (int b = 0; b < wall.axis; ++b) stride *= static_cast<std::uint32_t>(cells[b]);
    out[found++] = {w, stride, floor_index(wall.position(time) + shift[wall.axis] - origin[wall.axis])};
  }
  return found;
}

// Fills cell c of `members` particles, if a cut layer holds it and it has
// fewer than `fill`, up to that many with ghost particles keyed by (seed,
// step, key), key being the cell's number in the whole grid
// (SrdCells::cell_key); a cell cut by two walls (a corner) takes the first one's.
// Returns how many ghosts it added.
template <int D>
GRANFLOW_HD inline std::uint32_t fill_cut_cell(CellSums<D>& sums, std::uint32_t members, std::uint32_t c,
                                               std::uint64_t key, const CutLayer* cuts, int cut_count, const Wall* walls,
                                               const std::int32_t* cells, double fill, double time,
                                               double particle_mass, std::uint64_t seed, std::uint64_t step) {
  for (int q = 0; q < cut_count; ++q) {
    const CutLayer& cut = cuts[q];
    const Wall& wall = walls[cut.wall];
    const auto along = static_cast<std::uint32_t>(cells[wall.axis]);
    if (static_cast<std::int64_t>((c / cut.stride) % along) != cut.layer) continue;
    const int missing = ghost_count(members, fill);
    if (missing == 0) return 0;
    add_ghosts_to_sums<D>(sums, missing, wall, time, particle_mass, seed, step, key);
    return static_cast<std::uint32_t>(missing);
  }
  return 0;
}

// The mass-weighted offset along y of a particle at shifted height y from
// its cell's centre, the lever arm of the cell's angular momentum.
GRANFLOW_HD inline double moment_offset(double mass, double y) {
  return mass * (y - static_cast<double>(floor_index(y)) - 0.5);
}

// The global thermostat's update of one velocity v (in place): its cell's
// mean less the global drift, plus `factor` times its velocity relative to
// the mean as the cell sees it (a particle beyond a Lees-Edwards plane moves
// with `image_velocity` more along x).
template <int D>
GRANFLOW_HD inline void thermostat_velocity(double* v, const double* mean, const double* drift, double factor,
                                            double image_velocity) {
  for (int a = 0; a < D; ++a) {
    double u = v[a] - mean[a];
    if (a == 0) u += image_velocity;
    v[a] = mean[a] - drift[a] + factor * u - (a == 0 ? image_velocity : 0.0);
  }
}

// The cell's mean velocity V and temperature theta = sum m |v - V|^2 / (D
// members) from its sums; drift[a] = V - reference, for the moments.
template <int D>
GRANFLOW_HD inline void finish_sums(const CellSums<D>& s, double members, double* velocity, double& theta,
                                    double* drift) {
  double variance = s.squares;
  for (int a = 0; a < D; ++a) {
    drift[a] = s.sum[a] / s.mass;
    variance -= s.sum[a] * drift[a];
    velocity[a] = s.reference[a] + drift[a];
  }
  theta = (variance > 0.0 ? variance : 0.0) / (D * members);
}

// What the granular rule needs of a cell's collision.
struct GranularParameters {
  bool on = false;
  double restitution = 1.0, diameter = 0.0, dt = 1.0;
};

// The collision operator (a D x D matrix) of cell c at `step`: the identity
// for fewer than two members (one particle has no thermal velocity), else the
// rotation with its random axis and, granular, the cell's eps_eff; `clamped`
// tells whether eps_eff fell below 0.
template <int D>
GRANFLOW_HD inline void cell_collision_matrix(const CellRotation<D>& base, const GranularParameters& granular,
                                              std::uint64_t seed, std::uint64_t step, std::uint64_t c, double members,
                                              double theta, double* matrix, bool& clamped) {
  clamped = false;
  if (members < 2) {
    for (int a = 0; a < D * D; ++a) matrix[a] = a % (D + 1) == 0 ? 1.0 : 0.0;
    return;
  }
  CellRotation<D> r = cell_rotation<D>(base, seed, step, c);
  if (granular.on) r.eps = effective_restitution(granular.restitution, granular.diameter, members, theta, granular.dt, clamped);
  r.matrix(matrix);
}

// The x momentum the collision moves across the cell's centre plane,
// sum m dv_x (y - y_cell) = ((M - 1) row x) . sum m (v - V) (y - y_cell).
template <int D>
GRANFLOW_HD inline double collisional_transfer(const double* matrix, const double* moment) {
  double sum = -moment[0];
  for (int b = 0; b < D; ++b) sum += matrix[b] * moment[b];
  return sum;
}

}  // namespace granflow::srd
