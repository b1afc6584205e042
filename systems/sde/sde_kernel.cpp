#include "systems/sde/sde_kernel.hpp"

#include <algorithm>
#include <cmath>

#include "engine/core/stream_ids.hpp"
#include "systems/sde/gaussian_noise.hpp"

namespace granflow::sde {

template <int D>
void sde_step_range(double* x, double* v, std::size_t begin, std::size_t end, const StepInput& in) {
  static_assert(D >= 1 && D <= 3, "one Philox call gives four normals: at most 3 components");
  constexpr std::size_t block = 256;
  alignas(64) std::uint32_t words[4][block];
  alignas(64) float noise[4][block];
  alignas(64) float radius[block];
  alignas(64) float angle[block];
  const auto k0 = static_cast<std::uint32_t>(in.seed), k1 = static_cast<std::uint32_t>(in.seed >> 32);
  const auto counter2 = static_cast<std::uint32_t>(in.step);
  constexpr std::uint32_t counter3 = stream::sde_noise << 16;
  const OrnsteinUhlenbeck ou = exact_velocity_update(in.model, in.time, in.dt);
  const double gamma = in.model.friction(in.time);
  const double diffusivity = in.model.diffusivity(in.time);
  const double h = in.dt;
  for (std::size_t first = begin; first < end; first += block) {
    const std::size_t n = std::min(block, end - first);
    // Random words, then normals, for the block: separate branch-free loops
    // over arrays, which the compiler turns into vector code.
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint64_t item = first + k;
      std::uint32_t c0 = static_cast<std::uint32_t>(item), c1 = static_cast<std::uint32_t>(item >> 32);
      std::uint32_t c2 = counter2, c3 = counter3;
      philox4x32_10(c0, c1, c2, c3, k0, k1);
      words[0][k] = c0;
      words[1][k] = c1;
      words[2][k] = c2;
      words[3][k] = c3;
    }
    // Box-Muller (gaussian_noise.hpp), with cos and sin in loops of their
    // own: fused into sincos, which returns through pointers, they would not vectorise.
    for (int pair = 0; pair < (D + 1) / 2; ++pair) {
      for (std::size_t k = 0; k < n; ++k) {
        radius[k] = box_muller_radius(words[2 * pair][k]);
        angle[k] = box_muller_angle(words[2 * pair + 1][k]);
      }
      for (std::size_t k = 0; k < n; ++k) noise[2 * pair][k] = radius[k] * std::cos(angle[k]);
      if (2 * pair + 1 < D)
        for (std::size_t k = 0; k < n; ++k) noise[2 * pair + 1][k] = radius[k] * std::sin(angle[k]);
    }
    double* xb = x + first * D;
    double* vb = v + first * D;
    if (in.scheme == Scheme::euler_maruyama) {
      for (std::size_t k = 0; k < n; ++k)
        for (int a = 0; a < D; ++a)
          euler_maruyama_step(xb[k * D + a], vb[k * D + a], gamma, diffusivity, h, noise[a][k]);
    } else {
      for (std::size_t k = 0; k < n; ++k)
        for (int a = 0; a < D; ++a) drift_ou_drift_step(xb[k * D + a], vb[k * D + a], ou, h, noise[a][k]);
    }
  }
}

template void sde_step_range<1>(double*, double*, std::size_t, std::size_t, const StepInput&);
template void sde_step_range<2>(double*, double*, std::size_t, std::size_t, const StepInput&);
template void sde_step_range<3>(double*, double*, std::size_t, std::size_t, const StepInput&);

}  // namespace granflow::sde
