#pragma once
// Units of the configuration keys that scenarios share, given to every
// registered scenario's schema (a key a schema lacks is skipped), so that
// `granflow keys` shows them and docs/units.md can list them. A scenario's
// own keys declare theirs with ConfigSchema::unit.

#include <string>
#include <utility>
#include <vector>

#include "engine/core/config.hpp"
#include "engine/core/units.hpp"

namespace granflow {

inline void declare_key_units(ConfigSchema& schema) {
  // "s" is the SI second: checkpoint intervals are wall-clock time.
  static const std::vector<std::pair<std::string, std::string>> known{
      {"system.radius", unit::length},          {"system.box_length", unit::length},
      {"system.mass", unit::mass},              {"initial.speed", unit::velocity},
      {"initial.temperature", unit::energy},    {"initial.equilibration_collisions", unit::none},
      {"collision.restitution", unit::none},    {"collision.wall_restitution", unit::none},
      {"collision.contact_time", unit::time},   {"collision.collapse_rate_factor", unit::none},
      {"collision.viscoelastic_speed", unit::velocity},
      {"run.t_stop", unit::time},               {"run.dt", unit::time},
      {"run.max_collisions_per_particle", unit::none}, {"run.min_energy_fraction", unit::none},
      {"output.interval", unit::time},          {"output.first", unit::time},
      {"output.checkpoint_interval", "s"},      {"msd.sample_interval", unit::time},
      {"gas.radius", unit::length},             {"gas.box_length", unit::length},
      {"gas.mass", unit::mass},                 {"gas.temperature", unit::energy},
      {"gas.restitution", unit::none},          {"gas.count", unit::none},
      {"sde.gamma0", unit::rate},               {"sde.diffusivity0", unit::diffusivity},
      {"sde.tau0", unit::time},                 {"bed.height", unit::length},
      {"bed.packing_fraction", unit::none},     {"bed.melt_collisions", unit::none},
      {"projectile.mass", unit::mass},          {"projectile.radius", unit::length},
      {"projectile.speed", unit::velocity},     {"projectile.x", unit::length},
      {"projectile.y", unit::length},           {"projectile.mass_ratio", unit::none},
      {"projectile.radius_ratio", unit::none},  {"target.mass", unit::mass},
      {"target.radius", unit::length},          {"scan.max_ratio", unit::none},
      {"crater.displacement_threshold", unit::none},  // in bed radii
      {"mixture.heavy_fraction", unit::none},   {"mixture.mass_ratio", unit::none},
      {"sampling.collisions_between", unit::none}, {"sampling.equilibration_collisions", unit::none},
  };
  for (const auto& [key, unit] : known)
    if (schema.find(key) && schema.find(key)->unit.empty()) schema.unit(key, unit);
}

}  // namespace granflow
