#pragma once
// The fluid's global (mass-weighted) mean velocity, total mass and granular
// temperature sum m |v - <v>|^2 / (D N), summed in a fixed order: what the
// state observer, the velocity distribution and the thermostat share. Over
// a part of the system (observers that run by rank) the sums are totalled
// over the ranks.

#include "components/mass.hpp"
#include "components/velocity.hpp"
#include "engine/core/deterministic_sum.hpp"
#include "engine/core/observed_part.hpp"
#include "engine/core/world.hpp"

namespace granflow::srd {

template <int D>
struct GlobalMotion {
  Vec<D> mean = Vec<D>::Zero();
  double total_mass = 0.0;
  double granular_temperature = 0.0;
  double particles = 0.0;
};

// particle_mass: the mass of every particle where the World has no Mass column.
template <int D>
GlobalMotion<D> global_motion(const Velocity<D>& velocity, const Mass* masses, double particle_mass,
                              bool with_temperature = true, const ObservedPart& part = {}) {
  const double* mass = masses ? masses->data() : nullptr;
  const auto m = [&](std::size_t i) { return mass ? mass[i] : particle_mass; };
  const std::size_t n = velocity.size();
  std::vector<double> sums{deterministic_sum(n, m), static_cast<double>(n)};
  for (int a = 0; a < D; ++a)
    sums.push_back(deterministic_sum(n, [&](std::size_t i) { return m(i) * velocity[i][a]; }));
  sums = part.total(sums);
  GlobalMotion<D> out;
  out.total_mass = sums[0];
  out.particles = sums[1];
  for (int a = 0; a < D; ++a) out.mean[a] = sums[2 + static_cast<std::size_t>(a)] / out.total_mass;
  if (with_temperature)
    out.granular_temperature =
        part.total(deterministic_sum(n, [&](std::size_t i) { return m(i) * (velocity[i] - out.mean).squaredNorm(); })) /
        (D * out.particles);
  return out;
}
// An observer's: the particles its view holds, totalled over the ranks
// where it holds a part.
template <int D, class ObserverView>
GlobalMotion<D> observed_motion(const ObserverView& view, double particle_mass) {
  const Mass* mass = view.template has<Mass>() ? &view.template read<Mass>() : nullptr;
  return global_motion<D>(view.template read<Velocity<D>>(), mass, particle_mass, true, view.part());
}
template <int D>
GlobalMotion<D> global_motion(const World& world, double particle_mass, bool with_temperature = true) {
  return global_motion<D>(world.component<Velocity<D>>(),
                          world.has_component<Mass>() ? &world.component<Mass>() : nullptr, particle_mass,
                          with_temperature);
}

}  // namespace granflow::srd
