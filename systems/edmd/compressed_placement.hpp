#pragma once
// Dense disordered packings by compression: random sequential addition at a
// packing fraction it reaches easily, then the radii grown towards the
// requested ones in steps of 1 %. After each step, overlapping pairs (and
// particles reaching into a wall) are pushed apart until none overlaps, and
// a short elastic event-driven run lets the packing flow: a compression by
// growing spheres like Lubachevsky & Stillinger's (J. Stat. Phys. 60, 561
// (1990)), with the growth in steps rather than during the collisions.
// Without the runs, every pair pushed apart would stay just touching, and
// each step would have to push the whole contact network apart again (at
// 0.5 in 3D, hundreds of sweeps a step); with them a few sweeps do. The
// packing it returns is disordered but not yet in equilibrium: an elastic
// run turns it into the equilibrium fluid, also past the freezing point
// (0.494 in 3D), where a lattice would stay solid.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <fmt/format.h>

#include "components/box.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/vector.hpp"
#include "components/velocity.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/world.hpp"
#include "engine/run/preparation.hpp"
#include "systems/edmd/elastic_preparation.hpp"
#include "systems/edmd/event_driven_gas.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "systems/initial/placement_grid.hpp"
#include "systems/initial/random_placement.hpp"

namespace granflow {

// The densest packing fraction compression is asked for: beyond it the
// relaxation slows down towards jamming, and the hard-sphere (disk) fluid
// is far past its freezing point.
template <int D>
constexpr double compression_limit() {
  return D == 3 ? 0.55 : 0.72;
}

namespace compression_detail {

// Pushes overlapping pairs apart, Gauss-Seidel fashion, until a whole sweep
// moves nothing; returns the sweeps it took, or -1 if `max_sweeps` did not
// suffice. Pairs end at least (1 + 2e-9) times their contact distance apart.
template <int D>
int push_apart(const Box<D>& box, const std::vector<double>& radius, std::vector<Vec<D>>& x, int max_sweeps) {
  constexpr double separation = 1e-3;
  const std::size_t count = x.size();
  PlacementRegion<D> everywhere;
  everywhere.upper = box.length;
  PlacementGrid<D> grid(box, everywhere, 2.0 * *std::max_element(radius.begin(), radius.end()), count);
  const auto keep_inside = [&](std::size_t i) {
    for (int a = 0; a < D; ++a) {
      if (box.periodic[a]) {
        x[i][a] -= box.length[a] * std::floor(x[i][a] / box.length[a]);
        if (x[i][a] >= box.length[a]) x[i][a] = 0.0;
      } else {
        x[i][a] = std::clamp(x[i][a], radius[i] * (1 + 4e-9), box.length[a] - radius[i] * (1 + 4e-9));
      }
    }
  };
  const auto push_pair = [&](std::size_t i, std::size_t j) {
    Vec<D> d = x[j] - x[i];
    for (int a = 0; a < D; ++a)
      if (box.periodic[a]) d[a] -= box.length[a] * std::round(d[a] / box.length[a]);
    const double contact = radius[i] + radius[j];
    const double distance = d.norm();
    if (distance >= contact * (1 + 2e-9)) return false;
    Vec<D> normal = Vec<D>::Zero();
    if (distance > 0.0) normal = d / distance;
    else normal[0] = 1.0;  // coincident centres: any direction separates them
    // A little beyond contact: a pair left exactly touching is overlapped
    // again by the next push of either particle, and sweeps multiply.
    const Vec<D> shift = 0.5 * (contact * (1 + separation) - distance) * normal;
    x[i] -= shift;
    x[j] += shift;
    keep_inside(i);
    keep_inside(j);
    return true;
  };
  // Walls hold particles that reach into them before the first sweep.
  for (std::size_t i = 0; i < count; ++i) keep_inside(i);
  for (int sweep = 1; sweep <= max_sweeps; ++sweep) {
    grid.clear();
    for (std::size_t i = 0; i < count; ++i) grid.insert(i, x[i]);
    bool moved = false;
    for (std::size_t i = 0; i < count; ++i)
      grid.any_near(x[i], [&](std::size_t j) {
        if (j > i) moved |= push_pair(i, j);  // each pair once
        return false;
      });
    if (!moved) return sweep;
  }
  return -1;
}

}  // namespace compression_detail

// Centres for particles of `radius` filling the whole box, compressed as
// described above from random sequential addition at 0.6 of its jamming
// fraction (or at the requested packing fraction, if that is lower).
template <int D>
std::vector<Vec<D>> place_compressed(const Box<D>& box, const std::vector<double>& radius, std::uint64_t seed,
                                     const Preparation& preparation = {}) {
  if (radius.empty()) return {};
  double occupied = 0.0;
  for (const double r : radius) occupied += ball_volume<D>(r);
  const double fraction = occupied / box.volume();
  if (fraction > compression_limit<D>() * (1 + 1e-9))
    throw PlacementError(fmt::format("cannot compress {} particles to packing fraction {:.4f}: compression is "
                                     "offered up to {} in {}D; lower system.count or system.radius",
                                     radius.size(), fraction, compression_limit<D>(), D));
  const double start = std::min(fraction, 0.6 * random_sequential_jamming_fraction<D>());
  double scale = std::pow(start / fraction, 1.0 / D);
  std::vector<double> grown(radius.size());
  const auto grow_to = [&](double s) {
    for (std::size_t i = 0; i < radius.size(); ++i) grown[i] = s * radius[i];
  };
  grow_to(scale);
  PlacementRegion<D> everywhere;
  everywhere.upper = box.length;
  std::vector<Vec<D>> x = place_randomly<D>(box, everywhere, grown, seed, preparation.named("random placement"));

  World world(radius.size());
  world.emplace_resource<Box<D>>(box);
  world.add_component<Mass>().values.assign(radius.size(), 1.0);
  world.add_component<Radius>();
  world.add_component<Position<D>>();
  auto& velocity = world.add_component<Velocity<D>>();
  for (std::size_t i = 0; i < radius.size(); ++i) {
    Philox random(stream::compression_velocity, seed, 0, i);
    velocity[i] = random_direction<D>(random);
  }
  // One per cent in radius per step: overlaps of at most 1 % of a diameter;
  // two collisions per particle between steps.
  constexpr double step = 1.01;
  constexpr double flow_collisions = 2.0;
  constexpr int max_sweeps = 20000;
  const auto compressing = preparation.named("compression");
  const Preparation flowing{compressing.phase, {}, preparation.interrupt};  // progress is the steps'
  const double first = scale;
  while (scale < 1.0) {
    compressing.stop_if_interrupted();
    compressing.progress(std::log(scale / first) / std::log(1.0 / first));
    scale = std::min(1.0, scale * step);
    grow_to(scale);
    if (compression_detail::push_apart<D>(box, grown, x, max_sweeps) < 0)
      throw PlacementError(fmt::format("compression to packing fraction {:.4f} stalled at {:.4f}: the packing is "
                                       "near jamming; lower system.count or system.radius",
                                       fraction, fraction * std::pow(scale, D)));
    if (scale == 1.0 || radius.size() < 2) break;
    world.template component<Radius>().values = grown;
    world.template component<Position<D>>().values = x;
    edmd::EventDrivenGas<D> gas(world, edmd::CollisionParameters{}, false);
    gas.start(0.0);
    const double collisions = std::ceil(flow_collisions * static_cast<double>(radius.size()) / 2);
    edmd::run_elastic_preparation(gas, static_cast<std::uint64_t>(collisions), flowing);
    gas.synchronize(gas.time());
    x = world.template component<Position<D>>().values;
  }
  return x;
}

}  // namespace granflow
