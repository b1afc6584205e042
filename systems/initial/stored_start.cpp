// Stored starts, compiled once: the keys a stored state sets and the
// particles it puts into the world, checked, for 2 and 3 dimensions.

#include "systems/initial/stored_start.hpp"

#include <fmt/ranges.h>

#include <stdexcept>

#include "systems/initial/placement_grid.hpp"

namespace granflow {

double uniform(const std::vector<double>& values, const std::string& what, const std::string& key,
               const StoredState& s) {
  if (values.empty())
    throw InputError(fmt::format("initial.from: {} has no particle {} (the run needs them)", s.source, what));
  const auto [low, high] = std::minmax_element(values.begin(), values.end());
  if (*high > *low * (1 + 1e-12))
    throw InputError(fmt::format("initial.from: {} holds {} from {} to {}; in this scenario every particle has the "
                                 "one {} ({})",
                                 s.source, what, *low, *high, what, key));
  return *low;
}

void adopt_stored_layout(Config& config, const StoredState& s) {
  const auto has = [&](const char* key) { return config.schema().find(key) != nullptr; };
  if (s.count == 0) throw InputError(fmt::format("initial.from: {} holds no particles", s.source));
  if (has("system.dimension")) config.set("system.dimension", static_cast<std::int64_t>(s.dimension));
  if (has("system.count")) config.set("system.count", static_cast<std::int64_t>(s.count));
  if (has("system.box_length")) {
    const auto [low, high] = std::minmax_element(s.edges.begin(), s.edges.end());
    if (*high > *low * (1 + 1e-12))
      throw InputError(fmt::format("initial.from: {} has a box of edges {}; this scenario's box is a square or cube "
                                   "(system.box_length)",
                                   s.source, fmt::join(s.edges, " x ")));
    config.set("system.box_length", *low);
  }
  if (has("system.box")) config.set("system.box", s.edges);
  if (has("system.boundary")) {
    const auto periodic = static_cast<std::size_t>(std::count(s.periodic.begin(), s.periodic.end(), true));
    if (periodic != 0 && periodic != s.periodic.size())
      throw InputError(fmt::format("initial.from: {} is periodic along some axes only; this scenario's boundary is "
                                   "the same on every axis (system.boundary)",
                                   s.source));
    config.set("system.boundary", std::string(periodic ? "periodic" : "reflecting"));
  }
  if (has("system.cells")) {  // SRD: the box in cells of size 1, a whole number of particles per cell
    double cells = 1.0;
    for (double edge : s.edges) {
      if (edge != std::round(edge) || edge < 2)
        throw InputError(fmt::format("initial.from: {} has a box of edges {}; an SRD box is a whole number (at "
                                     "least 2) of cells of size 1 along each axis (system.cells)",
                                     s.source, fmt::join(s.edges, " x ")));
      cells *= edge;
    }
    config.set("system.cells", s.edges);
    const double per_cell = static_cast<double>(s.count) / cells;
    if (has("srd.particles_per_cell")) {
      if (per_cell != std::round(per_cell))
        throw InputError(fmt::format("initial.from: {} holds {} particles in {} cells: not a whole number per cell "
                                     "(srd.particles_per_cell)",
                                     s.source, s.count, cells));
      config.set("srd.particles_per_cell", static_cast<std::int64_t>(per_cell));
    }
  }
  for (const char* key : {"system.radius", "particle.radius"})
    if (has(key)) config.set(key, uniform(s.radius, "radii", key, s));
}

void adopt_stored_state(Config& config) {
  if (!starts_from_stored_state(config)) return;
  // The layout alone: a result file's positions and velocities stay in it.
  const StoredState s = StoredFrame(config.text("initial.from"), config.integer("initial.frame")).layout();
  adopt_stored_layout(config, s);
  for (const char* key : {"system.mass", "particle.mass"})
    if (config.schema().find(key)) config.set(key, uniform(s.mass, "masses", key, s));
}

void adopt_stored_state_as_one_run(Config& config) {
  if (starts_from_stored_state(config) && config.integer("run.runs") != 1)
    throw ConfigError(fmt::format("initial.from with run.runs = {}: every run would start from the same stored state "
                                  "and, the dynamics being deterministic, repeat it; set run.runs = 1",
                                  config.integer("run.runs")));
  adopt_stored_state(config);
}

namespace {

template <int D>
void check_stored_layout(const StoredState& s, bool has_velocity) {
  if (s.dimension != static_cast<std::size_t>(D))
    throw InputError(fmt::format("initial.from: {} is {}D; the run is {}D", s.source, s.dimension, D));
  if (!has_velocity)
    throw InputError(fmt::format("initial.from: {} has no velocities (H5MD velocity, GSD particles/velocity, "
                                 "extended XYZ velo, vel or momenta with masses)",
                                 s.source));
}

// Particle i's stored position and velocity (D values each), checked and
// put into the box: wrapped along periodic axes, else kept `margin` inside
// the walls.
template <int D>
void place_particle(const Box<D>& box, const StoredState& s, std::size_t i, const double* stored_x,
                    const double* stored_v, double radius, const StoredStateLimits& limits, Vec<D>& x_out,
                    Vec<D>& v_out) {
  for (int a = 0; a < D; ++a) {
    double x = stored_x[a];
    const double v = stored_v[a];
    if (!std::isfinite(x) || !std::isfinite(v))
      throw InputError(fmt::format("initial.from: {}: particle {} has position or velocity {} along axis {}", s.source,
                                   i, std::isfinite(x) ? v : x, a));
    const double length = box.length[static_cast<std::size_t>(a)];
    // Single-precision formats (GSD) store a position at the edge as the edge.
    const double slack = 1e-6 * length;
    if (box.periodic[static_cast<std::size_t>(a)]) {
      x -= length * std::floor(x / length);
      if (x >= length) x = 0.0;
    } else {
      const double margin = limits.radius_fits ? radius : 0.0;
      if (x < margin - slack || x > length - margin + slack)
        throw InputError(fmt::format("initial.from: {}: particle {} at {} along axis {} is outside the box [0, {}]{}",
                                     s.source, i, x, a, length,
                                     limits.radius_fits ? fmt::format(" (its radius {} must fit)", radius) : ""));
      x = std::clamp(x, margin, length - margin);
    }
    x_out[a] = x;
    v_out[a] = v;
  }
}

}  // namespace

template <int D>
void place_stored_state(World& world, const std::array<double, D>& edges, const std::array<bool, D>& periodic,
                        const StoredState& s, const StoredStateLimits& limits) {
  Box<D> box;
  box.length = edges;
  box.periodic = periodic;
  check_stored_layout<D>(s, !s.velocity.empty());
  // Point particles (SRD) have neither radii nor masses of their own.
  const bool spheres = world.has_component<Radius>();
  if (spheres && (s.radius.empty() || s.mass.empty()))
    throw InputError(fmt::format("initial.from: {} has no particle {}", s.source, s.radius.empty() ? "radii" : "masses"));
  world.resize(s.count);
  auto& position = world.component<Position<D>>().values;
  auto& velocity = world.component<Velocity<D>>().values;
  std::vector<double> radius(s.count, 0.0);
  double* radius_column = spheres ? world.component<Radius>().values.data() : nullptr;
  double* mass_column = spheres ? world.component<Mass>().values.data() : nullptr;
  double largest = 0.0;
  for (std::size_t i = 0; i < s.count; ++i) {
    if (spheres) {
      radius[i] = radius_column[i] = s.radius[i];
      mass_column[i] = s.mass[i];
      largest = std::max(largest, radius[i]);
      if (!(radius[i] > 0) || !(s.mass[i] > 0) || !std::isfinite(radius[i]) || !std::isfinite(s.mass[i]))
        throw InputError(fmt::format("initial.from: {}: particle {} has radius {} and mass {}; both must be positive",
                                     s.source, i, radius[i], s.mass[i]));
    }
    place_particle<D>(box, s, i, &s.position[i * D], &s.velocity[i * D], radius[i], limits, position[i], velocity[i]);
  }
  // A run of several kinds of particle takes each particle's kind as stored.
  if (world.has_component<Species>()) {
    if (s.species.size() != s.count)
      throw InputError(fmt::format("initial.from: {} has no particle species (H5MD species, GSD typeid, extended "
                                   "XYZ typeid or species); this run has several kinds of particle",
                                   s.source));
    auto& species = world.component<Species>();
    for (std::size_t i = 0; i < s.count; ++i) species[i] = static_cast<typename Species::value_type>(s.species[i]);
  }
  if (!spheres) return;
  // No two particles may overlap (beyond round-off of the stored positions).
  PlacementRegion<D> everywhere;
  everywhere.upper = box.length;
  PlacementGrid<D> grid(box, everywhere, 2 * largest, s.count);
  for (std::size_t i = 0; i < s.count; ++i) {
    std::size_t other = 0;
    double distance = 0.0;
    const bool overlaps = grid.any_near(position[i], [&](std::size_t k) {
      Vec<D> d = position[i] - position[k];
      for (int a = 0; a < D; ++a)
        if (box.periodic[static_cast<std::size_t>(a)]) d[a] -= box.length[a] * std::round(d[a] / box.length[a]);
      distance = d.norm();
      other = k;
      const double allowed = limits.overlap * std::min(radius[i], radius[k]) + 1e-9 * (radius[i] + radius[k]);
      return distance < radius[i] + radius[k] - allowed;
    });
    if (overlaps)
      throw InputError(fmt::format("initial.from: {}: particles {} and {} overlap (centres {:.6g} apart, radii {} "
                                   "and {}{})",
                                   s.source, other, i, distance, radius[other], radius[i],
                                   limits.overlap > 0 ? fmt::format("; at most {} of a radius is allowed", limits.overlap)
                                                      : ""));
    grid.insert(i, position[i]);
  }
}

template void place_stored_state<2>(World&, const std::array<double, 2>&, const std::array<bool, 2>&,
                                    const StoredState&, const StoredStateLimits&);
template void place_stored_state<3>(World&, const std::array<double, 3>&, const std::array<bool, 3>&,
                                    const StoredState&, const StoredStateLimits&);

template <int D>
void place_stored_part(World& world, const std::array<double, D>& edges, const std::array<bool, D>& periodic,
                       const StoredFrame& frame, const std::function<bool(const double* position)>& owns) {
  if (world.has_component<Radius>() || world.has_component<Species>())
    throw std::logic_error("a stored state is placed by part for point particles of one kind only");
  const StoredState& s = frame.layout();
  check_stored_layout<D>(s, frame.has_velocity());
  Box<D> box;
  box.length = edges;
  box.periodic = periodic;
  // Every reader checks every particle, so that all refuse a bad one alike.
  std::vector<Vec<D>> position, velocity;
  std::vector<std::uint32_t> index;
  constexpr std::size_t rows_per_read = std::size_t{1} << 18;
  Vec<D> x, v;
  for (std::size_t first = 0; first < s.count; first += rows_per_read) {
    const std::size_t rows = std::min(rows_per_read, s.count - first);
    const std::vector<double> xs = frame.positions(first, rows), vs = frame.velocities(first, rows);
    for (std::size_t k = 0; k < rows; ++k) {
      place_particle<D>(box, s, first + k, &xs[k * D], &vs[k * D], 0.0, {0.0, false}, x, v);
      if (!owns(x.data())) continue;
      position.push_back(x);
      velocity.push_back(v);
      index.push_back(static_cast<std::uint32_t>(first + k));
    }
  }
  world.resize(position.size());
  world.component<Position<D>>().values = std::move(position);
  world.component<Velocity<D>>().values = std::move(velocity);
  if (world.has_component<ParticleId>()) world.component<ParticleId>().values = std::move(index);
}

template void place_stored_part<2>(World&, const std::array<double, 2>&, const std::array<bool, 2>&,
                                   const StoredFrame&, const std::function<bool(const double*)>&);
template void place_stored_part<3>(World&, const std::array<double, 3>&, const std::array<bool, 3>&,
                                   const StoredFrame&, const std::function<bool(const double*)>&);

}  // namespace granflow
