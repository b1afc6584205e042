#pragma once
// The fluid's global (mass-weighted) mean velocity, total mass and granular
// temperature sum m |v - <v>|^2 / (D N), summed in a fixed order: what the
// state observer, the velocity distribution and the thermostat share.

#include "components/mass.hpp"
#include "components/velocity.hpp"
#include "engine/core/deterministic_sum.hpp"
#include "engine/core/world.hpp"

namespace granflow::srd {

template <int D>
struct GlobalMotion {
  Vec<D> mean = Vec<D>::Zero();
  double total_mass = 0.0;
  double granular_temperature = 0.0;
};

// particle_mass: the mass of every particle where the World has no Mass column.
template <int D>
GlobalMotion<D> global_motion(const Velocity<D>& velocity, const Mass* masses, double particle_mass,
                              bool with_temperature = true) {
  const double* mass = masses ? masses->data() : nullptr;
  const auto m = [&](std::size_t i) { return mass ? mass[i] : particle_mass; };
  const std::size_t n = velocity.size();
  GlobalMotion<D> out;
  out.total_mass = deterministic_sum(n, m);
  for (int a = 0; a < D; ++a)
    out.mean[a] = deterministic_sum(n, [&](std::size_t i) { return m(i) * velocity[i][a]; }) / out.total_mass;
  if (with_temperature)
    out.granular_temperature =
        deterministic_sum(n, [&](std::size_t i) { return m(i) * (velocity[i] - out.mean).squaredNorm(); }) /
        (D * static_cast<double>(n));
  return out;
}
template <int D>
GlobalMotion<D> global_motion(const World& world, double particle_mass, bool with_temperature = true) {
  return global_motion<D>(world.component<Velocity<D>>(),
                          world.has_component<Mass>() ? &world.component<Mass>() : nullptr, particle_mass,
                          with_temperature);
}

}  // namespace granflow::srd
