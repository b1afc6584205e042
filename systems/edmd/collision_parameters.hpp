#pragma once
// The collision.* keys of every event-driven scenario: normal and wall
// restitution (constant, or viscoelastic from the impact speed), the TC
// model's contact time and the collapse alarm.

#include <fmt/format.h>

#include <limits>

#include "engine/core/config.hpp"

namespace granflow::edmd {

struct CollisionParameters {
  double restitution = 1.0;
  double wall_restitution = 1.0;
  // TC model (Luding & McNamara 1998): a collision within contact_time of
  // either particle's previous collision is elastic.
  double contact_time = 0.0;
  // A collision rate this many times the rate expected from the kinetic
  // energy is taken as inelastic collapse.
  double collapse_rate_factor = 1000.0;
  // Viscoelastic spheres (viscoelastic_restitution.hpp): the speed g_ve of the
  // material; 0: the constant `restitution`.
  double viscoelastic_speed = 0.0;

  // collision.* keys, declared once for every event-driven scenario with that scenario's defaults.
  static void declare(ConfigSchema& schema, const CollisionParameters& defaults);
  static CollisionParameters from(const Config& config);
};

inline void CollisionParameters::declare(ConfigSchema& schema, const CollisionParameters& d) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  schema.real("collision.restitution", d.restitution, 0.0, 1.0, "normal restitution coefficient xi")
      .real("collision.wall_restitution", d.wall_restitution, 0.0, 1.0,
            "restitution of reflecting walls: the whole velocity is scaled by it (Poeschel & Schwager 2005)")
      .real("collision.contact_time", d.contact_time, 0.0, inf,
            "TC model (Luding & McNamara 1998): collisions within this time of a particle's previous collision "
            "are elastic")
      .real_or_infinite("collision.collapse_rate_factor", d.collapse_rate_factor, 10.0,
                        "collision-rate increase (at equal thermal speed) that is reported as inelastic collapse")
      .real("collision.viscoelastic_speed", d.viscoelastic_speed, 0.0, inf,
            "viscoelastic spheres (Schwager & Poeschel 2008): the material's speed g_ve, eps(g_n) = 1 - 1.1534 "
            "(g_n/g_ve)^(1/5) + ... for normal impact speed g_n; 0: the constant collision.restitution (which "
            "must then be 1 otherwise)");
}

inline CollisionParameters CollisionParameters::from(const Config& config) {
  CollisionParameters p;
  p.restitution = config.real("collision.restitution");
  p.wall_restitution = config.real("collision.wall_restitution");
  p.contact_time = config.real("collision.contact_time");
  p.collapse_rate_factor = config.real("collision.collapse_rate_factor");
  if (config.schema().find("collision.viscoelastic_speed")) {
    p.viscoelastic_speed = config.real("collision.viscoelastic_speed");
    if (p.viscoelastic_speed > 0.0 && p.restitution != 1.0)
      throw ConfigError(fmt::format("collision.viscoelastic_speed = {:g} sets the restitution from the impact speed; "
                                    "collision.restitution = {:g} would set it too: leave it at 1",
                                    p.viscoelastic_speed, p.restitution));
  }
  return p;
}

}  // namespace granflow::edmd
