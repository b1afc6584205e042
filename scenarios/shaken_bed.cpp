// Soft spheres shaken from below in a box split by a divider (the granular
// Maxwell demon: Schlichting & Nordmeier 1996, Eggers 1999, van der Meer et
// al. 2002): a floor moving as A sin(2 pi f t), gravity, linear
// spring-dashpot (or Hertz) contacts, walls on every side and a divider
// from the floor up to divider.height at divider.position along x. Strong
// shaking shares the spheres equally between the compartments; weak
// shaking lets them cluster in one. Observables: the asymmetry
// (N_L - N_R)/N, the flux over the divider each way, the energies and the
// balance of what the floor injects and the contacts dissipate, the
// contact count and coordination number.

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"
#include "engine/core/units.hpp"
#include "engine/run/run.hpp"
#include "engine/run/scenario.hpp"
#include "systems/dem/compartments.hpp"
#include "systems/dem/dem_setup.hpp"
#include "systems/dem/divided_bed.hpp"
#include "systems/dem/height_profiles.hpp"
#include "systems/initial/stored_start.hpp"

namespace granflow::scenarios {
namespace {

using dem::ContactLaw;
using dem::DemWall;

void build(Run& run) {
  constexpr int D = 3;
  const Config& c = run.config();
  const std::array<double, D> box = dem::box_from(c, "shaken_bed");
  const auto n = static_cast<std::size_t>(c.integer("system.count"));
  const double radius = c.real("particle.radius"), mass = c.real("particle.mass");
  dem::require_room(box, radius);
  const ContactLaw law = dem::law_from(c, c.real("contact.stiffness"), c.real("contact.restitution"));
  const double divider_x = c.real("divider.position") > 0 ? c.real("divider.position") : 0.5 * box[0];
  if (divider_x <= 2.0 * radius || divider_x >= box[0] - 2.0 * radius)
    throw ConfigError(fmt::format("divider.position = {} leaves a compartment narrower than a sphere (box x: {})",
                                  divider_x, box[0]));
  const double amplitude = c.real("shaking.amplitude");
  if (amplitude >= 0.25 * box[2])
    throw ConfigError(fmt::format("shaking.amplitude = {} exceeds a quarter of the box height (system.box z = {})",
                                  amplitude, box[2]));

  std::vector<DemWall> walls = dem::walls_or_box_sides(c, box, {false, false, false}, law);
  if (c.real("divider.height") > 0.0) walls.push_back(dem::divider_wall(0, divider_x, 2, c.real("divider.height"), law));

  const bool stored = starts_from_stored_state(c);
  std::vector<Vec<D>> sites;  // alternately left and right, from the floor up
  if (!stored)
    sites = dem::divided_bed_sites(box, divider_x, n, radius,
                                   (c.text("shaking.motion") == "wiggle" ? 2.0 : 1.0) * amplitude);
  dem::start_or_resume(run, [&](World& world) {
    if (stored) {
      dem::add_spheres(world, n, radius, mass);
      place_stored_state<D>(world, box, {false, false, false}, stored_state_of(c), dem::stored_state_limits);
      return;
    }
    // Over ranks each makes its part of the bed.
    const std::vector<std::size_t> made =
        dem::sites_made_here(c, run.communicator(), box, {false, false, false}, sites, radius);
    auto [x, v] = dem::add_spheres(world, made, n, run.communicator(), radius, mass);
    for (std::size_t k = 0; k < made.size(); ++k) {
      x[k] = sites[made[k]];
      Philox random(stream::dem_initial, run.seed(), 0, made[k]);
      for (int a = 0; a < D; ++a) v[k][a] = 0.1 * random.normal();
    }
  });
  std::vector<Vec<D>>().swap(sites);
  const auto outputs = std::make_shared<EveryTime>(c.real("output.interval"), c.real("run.t_stop"));
  const double dt = dem::add_dem_step(run, box, {false, false, false}, law, walls, dem::damping_key(c), outputs);
  dem::add_compartments<D>(run, outputs, divider_x, c.real("output.average_after"));
  dem::HeightProfileGeometry profile;
  profile.height = box[2];
  profile.layer = 2.0 * radius;
  profile.area = divider_x * box[1];
  profile.split_axis = 0;
  profile.split_at = divider_x;
  profile.area_right = (box[0] - divider_x) * box[1];
  profile.average_from = c.real("output.average_after");
  dem::add_height_profiles<D>(run, outputs, profile, dt);
}

}  // namespace

GRANFLOW_REGISTER_SCENARIO(shaken_bed, Scenario{
  .name = "shaken_bed",
  .summary = "soft spheres shaken in a box split by a divider: the granular Maxwell demon (asymmetry against time)",
  .default_output = "shaken_bed.h5md",
  .keys = [](ConfigSchema& s) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    dem::declare_dem_keys(s, dem::DemDefaults{});
    declare_stored_start_keys(s);
    s.real("divider.position", 0.0, 0.0, inf, "x of the divider (0: the middle of the box)")
        .real("divider.height", 8.0, 0.0, inf, "the divider reaches from the floor to this height (0: no divider)")
        .real("output.average_after", 100.0, 0.0, inf, "time after which a and |a| are averaged (the attributes "
              "asymmetry_time_mean, asymmetry_abs_mean) and the flux sampled for Eggers' fit");
    s.fixed_on_resume("output.average_after");
    s.unit("divider.position", unit::length).unit("divider.height", unit::length).unit("output.average_after", unit::time);
  },
  .build = build,
  .adopt = adopt_stored_state,
})

}  // namespace granflow::scenarios
