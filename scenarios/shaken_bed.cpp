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
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include "components/force.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/rng.hpp"
#include "engine/run.hpp"
#include "engine/scenario.hpp"
#include "engine/stream_ids.hpp"
#include "engine/units.hpp"
#include "systems/dem/compartments.hpp"
#include "systems/dem/dem_setup.hpp"
#include "systems/initial/stored_start.hpp"
#include "systems/dem/height_profiles.hpp"
#include "systems/initial/cubic_lattice.hpp"

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
  DemWall divider;
  divider.divider = true;
  divider.axis = 0;
  divider.height_axis = 2;
  divider.rest = divider_x;
  divider.top = c.real("divider.height");
  divider.law = law;
  if (divider.top > 0.0) walls.push_back(divider);

  // Spheres on a lattice from the floor up, alternately left and right.
  const double spacing = 2.2 * radius;
  const auto per_row = [&](double width) { return std::max(0, static_cast<int>(std::floor((width - 2 * radius) / spacing)) + 1); };
  const std::int64_t across_y = per_row(box[1]);
  const std::array<std::int64_t, 2> across_x{per_row(divider_x - 0.2 * radius), per_row(box[0] - divider_x - 0.2 * radius)};
  // Above the floor's highest point (2A with the wiggle law).
  const double floor_clearance = (c.text("shaking.motion") == "wiggle" ? 2.0 : 1.0) * amplitude + 1.1 * radius;
  const auto layers_needed = [&](int side) {
    const double per_layer = static_cast<double>(across_x[static_cast<std::size_t>(side)] * across_y);
    return per_layer > 0 ? std::ceil((static_cast<double>(n) / 2 + 1) / per_layer) : 1e300;
  };
  const double top = floor_clearance + spacing * std::max(layers_needed(0), layers_needed(1));
  const bool stored = starts_from_stored_state(c);
  if (!stored && top > box[2] - radius)
    throw ConfigError(fmt::format("system.count = {} spheres of radius {} do not fit below the top of the box "
                                  "(system.box z = {})", n, radius, box[2]));
  // Half of the spheres on each side (alternately), each half on a lattice from the floor up.
  std::array<std::vector<Vec<D>>, 2> sites;
  for (std::size_t side : {0u, 1u})
    if (!stored)
      sites[side] = cubic_sites({side == 0 ? radius + 0.1 * radius : divider_x + radius + 0.1 * radius, radius,
                                 floor_clearance},
                                spacing, {across_x[side], across_y}, (n + 1 - side) / 2);
  run.initial_state([&](World& world) {
    auto [x, v] = dem::add_spheres(world, n, radius, mass);
    if (stored) {
      place_stored_state<D>(world, box, {false, false, false}, stored_state_of(c), dem::stored_state_limits);
      return;
    }
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = sites[i % 2][i / 2];
      Philox random(stream::dem_initial, run.seed(), 0, i);
      for (int a = 0; a < D; ++a) v[i][a] = 0.1 * random.normal();
    }
  });
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
