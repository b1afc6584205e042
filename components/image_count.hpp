#pragma once
// How many times a particle has been wrapped across each periodic face
// (+1 leaving through the upper face): position + image * L is its unwrapped
// position, from which displacements and the MSD are measured.

#include <Eigen/Core>

#include "engine/core/world.hpp"

namespace granflow {
template <int D>
struct ImageCount : Column<Eigen::Matrix<std::int32_t, D, 1>> {
  static constexpr const char* key = "image_count";
};
}  // namespace granflow
