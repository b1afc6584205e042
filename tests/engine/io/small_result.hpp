#pragma once
// A small finished result file for the io tests: 3 particles in a periodic
// 3D box (edges 2, 3, 4), stored out of id order, with masses, radii,
// species, image counts and two frames (step 0 at t = 0 and step 10 at
// t = 0.5), as a run writes them.

#include <string>

#include "components/image_count.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/species.hpp"
#include "components/velocity.hpp"
#include "engine/core/world.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/io/particle_output.hpp"

namespace granflow::test {

// Particle id k sits at storage index stored_index[k].
inline constexpr std::uint32_t stored_index[3] = {2, 0, 1};

inline Vec<3> position_of(std::uint32_t id, int frame) { return Vec<3>(0.1 + id, 0.2 + id + frame, 0.3 + 0.5 * frame); }
inline Vec<3> velocity_of(std::uint32_t id, int frame) { return Vec<3>(-1.0 * id, frame, 0.25); }

inline World small_world() {
  World world;
  world.resize(3);
  auto& id = world.add_component<ParticleId>();
  auto& mass = world.add_component<Mass>();
  auto& radius = world.add_component<Radius>();
  auto& species = world.add_component<Species>();
  world.add_component<Position<3>>();
  world.add_component<Velocity<3>>();
  auto& image = world.add_component<ImageCount<3>>();
  for (std::uint32_t k = 0; k < 3; ++k) {
    const std::uint32_t i = stored_index[k];
    id[i] = k;
    mass[i] = 1.0 + k;
    radius[i] = 0.1 * (k + 1);
    species[i] = k == 2 ? 1 : 0;
    image[i] = Eigen::Matrix<std::int32_t, 3, 1>(static_cast<std::int32_t>(k), 0, -1);
  }
  return world;
}

inline void write_small_result(const std::string& path) {
  World world = small_world();
  H5mdFile file(path, "io_test");
  write_particle_constants(file, world);
  for (int frame = 0; frame < 2; ++frame) {
    for (std::uint32_t k = 0; k < 3; ++k) {
      world.component<Position<3>>()[stored_index[k]] = position_of(k, frame);
      world.component<Velocity<3>>()[stored_index[k]] = velocity_of(k, frame);
    }
    append_particle_frame<3>(file, world, 10 * frame, 0.5 * frame);
    file.append_observable("kinetic_energy", 10 * frame, 0.5 * frame, 1.0 + frame);
  }
  file.write_box({2.0, 3.0, 4.0}, {"periodic", "periodic", "periodic"});
  file.finish();
}

}  // namespace granflow::test
