#pragma once
// The collision.* keys of every event-driven scenario: normal and wall
// restitution, the TC model's contact time and the collapse alarm.

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
                        "collision-rate increase (at equal thermal speed) that is reported as inelastic collapse");
}

inline CollisionParameters CollisionParameters::from(const Config& config) {
  CollisionParameters p;
  p.restitution = config.real("collision.restitution");
  p.wall_restitution = config.real("collision.wall_restitution");
  p.contact_time = config.real("collision.contact_time");
  p.collapse_rate_factor = config.real("collision.collapse_rate_factor");
  return p;
}

}  // namespace granflow::edmd
