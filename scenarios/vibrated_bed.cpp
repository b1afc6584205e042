// A deep bed of soft spheres on a vibrating plate, periodic sideways: the
// floor moves as A (1 - cos 2 pi f t) under gravity along -z, from rest, as
// LAMMPS's fix wall/gran ... wiggle moves it (shaking.motion = "sine": A
// sin(2 pi f t) about 0). By default the bed
// of LAMMPS's shaken-bed benchmark (a 24 x 24 box, 10 580 spheres of
// diameter 1 and mass 1 on a simple cubic lattice of reduced density 1.05
// filling 0 <= x, y < 22.5, 0.6 <= z < 20.5; Hookean contacts k = 2000 with
// LAMMPS's damping rate gamma_n = 50, i.e. a damping force m_eff gamma_n
// times the normal speed; the floor at amplitude 0.5, period 1; starting at
// kT = 0.1), so that the two run side by side. Observables: the energies and
// the balance of what the floor injects and the contacts dissipate, the
// contact count and coordination number, and the packing fraction and
// granular temperature against height.

#include <fmt/format.h>

#include <array>
#include <limits>
#include <memory>
#include <vector>

#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/units.hpp"
#include "engine/run/run.hpp"
#include "engine/run/scenario.hpp"
#include "systems/dem/dem_setup.hpp"
#include "systems/dem/height_profiles.hpp"
#include "systems/initial/cubic_lattice.hpp"
#include "systems/initial/initial_velocities.hpp"
#include "systems/initial/stored_start.hpp"

namespace granflow::scenarios {
namespace {

using dem::ContactLaw;
using dem::DemWall;

void build(Run& run) {
  constexpr int D = 3;
  const Config& c = run.config();
  const std::array<double, D> box = dem::box_from(c, "vibrated_bed");
  const double radius = c.real("particle.radius"), mass = c.real("particle.mass");
  dem::require_room(box, radius);
  const ContactLaw law = dem::law_for_mass(c, 0.5 * mass);
  const std::vector<DemWall> walls = dem::walls_or_box_sides(c, box, {true, true, false}, dem::law_for_mass(c, mass));
  const auto n = static_cast<std::size_t>(c.integer("system.count"));
  const bool stored = starts_from_stored_state(c);
  std::vector<Vec<D>> sites;
  if (!stored) {
    const auto& fill = c.reals("bed.fill");
    if (fill.size() != 6)
      throw ConfigError(fmt::format("bed.fill has {} entries; it needs [x0, x1, y0, y1, z0, z1]", fill.size()));
    sites = cubic_sites_in({fill[0], fill[2], fill[4]}, {fill[1], fill[3], fill[5]},
                           std::cbrt(1.0 / c.real("bed.lattice_density")),
                           fmt::format("bed.lattice_density = {} over bed.fill", c.real("bed.lattice_density")));
    if (n > sites.size())
      throw ConfigError(fmt::format("system.count = {} exceeds the {} lattice sites of bed.fill at bed.lattice_density "
                                    "= {}", n, sites.size(), c.real("bed.lattice_density")));
    sites.resize(n);
  }
  const double temperature = c.real("bed.temperature");
  dem::start_or_resume(run, [&](World& world) {
    if (stored) {
      dem::add_spheres(world, n, radius, mass);
      place_stored_state<D>(world, box, {true, true, false}, stored_state_of(c), dem::stored_state_limits);
      return;
    }
    // Over ranks each makes its part of the bed; every velocity is drawn,
    // for the mean that they all lose.
    const std::vector<std::size_t> made =
        dem::sites_made_here(c, run.communicator(), box, {true, true, false}, sites, radius);
    auto [x, v] = dem::add_spheres(world, made, n, run.communicator(), radius, mass);
    std::vector<Vec<D>> velocities(n);
    draw_thermal_velocities<D>(velocities, temperature, mass, stream::dem_initial, run.seed());
    for (std::size_t k = 0; k < made.size(); ++k) {
      x[k] = sites[made[k]];
      v[k] = velocities[made[k]];
    }
  });
  std::vector<Vec<D>>().swap(sites);
  const auto outputs = std::make_shared<EveryTime>(c.real("output.interval"), c.real("run.t_stop"));
  const double dt = dem::add_dem_step(run, box, {true, true, false}, law, walls, dem::damping_key(c), outputs);
  dem::HeightProfileGeometry profile;
  profile.height = box[2];
  profile.layer = 2.0 * radius;
  profile.area = box[0] * box[1];
  profile.average_from = c.real("output.average_after");
  dem::add_height_profiles<D>(run, outputs, profile, dt);
}

}  // namespace

GRANFLOW_REGISTER_SCENARIO(vibrated_bed, Scenario{
  .name = "vibrated_bed",
  .summary = "a deep bed of soft spheres on a vibrating plate, periodic sideways (LAMMPS's shaken-bed workload)",
  .default_output = "vibrated_bed.h5md",
  .keys = [](ConfigSchema& s) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    dem::DemDefaults d;
    d.count = 10580;
    d.box = {24.0, 24.0, 80.0};
    d.stiffness = 2000.0;
    d.restitution = 0.5;
    d.amplitude = 0.5;
    d.frequency = 1.0;
    d.t_stop = 10.0;
    d.output_interval = 1.0;
    d.motion = "wiggle";
    dem::declare_dem_keys(s, d);
    declare_stored_start_keys(s);
    s.real("contact.damping_rate", 50.0, 0.0, inf,
           "LAMMPS's gamma_n: damping force m_eff gamma_n times the normal speed (0: from contact.restitution)")
        .real("output.average_after", 2.0, 0.0, inf,
              "time from which the height profiles are averaged (packing_fraction_profile_mean, temperature_profile_mean)")
        .real("bed.lattice_density", 1.05, 0.0, inf, "spheres per unit volume of the initial simple cubic lattice", true)
        .real_array("bed.fill", {0.0, 22.5, 0.0, 22.5, 0.6, 20.5}, -1e9, 1e9, 6, 6,
                    "[x0, x1, y0, y1, z0, z1]: the lattice sites filled, in this order, up to system.count")
        .real("bed.temperature", 0.1, 0.0, inf, "initial kT of the spheres (Maxwell-Boltzmann, no net momentum)");
    s.fixed_on_resume("output.average_after");
    s.unit("contact.damping_rate", unit::rate).unit("bed.lattice_density", "L-3").unit("bed.fill", unit::length)
        .unit("bed.temperature", unit::energy).unit("output.average_after", unit::time);
  },
  .build = build,
  .adopt = adopt_stored_state,
})

}  // namespace granflow::scenarios
