#pragma once
// The inner loop of an SDE step over a range of particles, compiled in its
// own translation unit (systems/sde/sde_kernel.cpp) with the flags that let
// the compiler vectorise the random numbers and the transcendental functions.

#include <cstddef>
#include <cstdint>

#include "systems/sde/sde_model.hpp"

namespace granflow::sde {

enum class Scheme { euler_maruyama, exact_ou };

struct StepInput {
  SdeModel model;
  Scheme scheme;
  double time;  // at the start of the step
  double dt;
  std::uint64_t seed;
  std::uint64_t step;
};

// x, v: D doubles per particle, particles [begin, end); particle i's noise is
// keyed by (sde_noise, seed, step, i).
template <int D>
void sde_step_range(double* x, double* v, std::size_t begin, std::size_t end, const StepInput& input);

}  // namespace granflow::sde
