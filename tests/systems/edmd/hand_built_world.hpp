#pragma once
// Worlds of a few hand-placed particles for the hand-built engine checks.

#include <vector>

#include "components/box.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/core/world.hpp"

namespace granflow::edmd::testing {

template <int D>
struct ParticleSpec {
  Vec<D> position;
  Vec<D> velocity;
  double radius;
  double mass;
};

template <int D>
void build_world(World& world, const std::vector<ParticleSpec<D>>& particles, bool periodic = false,
                 double box_length = 1.0) {
  world.resize(particles.size());
  Box<D> box;
  box.length.fill(box_length);
  box.periodic.fill(periodic);
  world.emplace_resource<Box<D>>(box);
  auto& x = world.add_component<Position<D>>();
  auto& v = world.add_component<Velocity<D>>();
  auto& r = world.add_component<Radius>();
  auto& m = world.add_component<Mass>();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    x[i] = particles[i].position;
    v[i] = particles[i].velocity;
    r[i] = particles[i].radius;
    m[i] = particles[i].mass;
  }
}

// Storage index of the particle with a given id (the engine may reorder storage).
inline std::size_t index_of(const World& world, std::uint32_t id) {
  const auto& ids = world.component<ParticleId>();
  for (std::size_t i = 0; i < world.size(); ++i)
    if (ids[i] == id) return i;
  return world.size();
}

template <int D>
Vec<D> velocity_of(const World& world, std::uint32_t id) {
  return world.component<Velocity<D>>()[index_of(world, id)];
}
template <int D>
Vec<D> position_of(const World& world, std::uint32_t id) {
  return world.component<Position<D>>()[index_of(world, id)];
}

}  // namespace granflow::edmd::testing
