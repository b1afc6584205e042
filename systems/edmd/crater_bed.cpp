#include "systems/edmd/crater_bed.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "components/box.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/species.hpp"
#include "components/velocity.hpp"
#include "systems/edmd/gas_setup.hpp"
#include "systems/edmd/melted_lattice.hpp"

namespace granflow::edmd {

double bed_radius(const Config& config) {
  const double area = config.real("bed.height");  // the box is 1 wide
  return std::sqrt(config.real("bed.packing_fraction") * area /
                   (static_cast<double>(config.integer("system.count")) * std::numbers::pi));
}

void build_crater(World& world, const Config& config, const Preparation& preparation) {
  const auto count = static_cast<std::size_t>(config.integer("system.count"));
  const double r0 = bed_radius(config);
  const double big = config.real("projectile.radius_ratio") * r0;
  const double x = config.real("projectile.x"), y = config.real("projectile.y");
  const double height = config.real("bed.height");
  if (x - big < 0 || x + big > 1 || y + big > 1 || y - big < height)
    throw ConfigError(fmt::format("projectile of radius {:.4g} at ({}, {}) must lie inside the box and above the bed "
                                  "(bed.height = {}); change projectile.x/y or projectile.radius_ratio",
                                  big, x, y, height));
  world.resize(count + 1);
  Box<2> box;
  box.length.fill(1.0);
  box.periodic.fill(false);
  world.emplace_resource<Box<2>>(box);
  auto& mass = world.add_component<Mass>();
  auto& radius = world.add_component<Radius>();
  auto& species = world.add_component<Species>();
  auto& position = world.add_component<Position<2>>();
  auto& velocity = world.add_component<Velocity<2>>();
  Box<2> bed_region;
  bed_region.length = {1.0, height};
  bed_region.periodic.fill(false);
  edmd::check_equilibration_length<2>(bed_region, count, r0, config.real("system.mass"), 1.0,
                                      config.real("bed.melt_collisions"),
                                      "bed.melt_collisions, bed.packing_fraction or system.count");
  const auto bed = place_melted_lattice(count, r0, 1.0, height, config.real("bed.melt_collisions"),
                                        static_cast<std::uint64_t>(config.integer("run.seed")), preparation);
  for (std::size_t i = 0; i < count; ++i) {
    mass[i] = config.real("system.mass");
    radius[i] = r0;
    position[i] = bed[i];
    velocity[i].setZero();
  }
  mass[count] = config.real("projectile.mass_ratio") * config.real("system.mass");
  radius[count] = big;
  species[count] = 1;
  position[count] = Vec<2>(x, y);
  velocity[count] = Vec<2>(0.0, -config.real("projectile.speed"));
}

}  // namespace granflow::edmd
