// The vectorised SDE kernel (compiled with -ffast-math, and -march=native
// unless GRANFLOW_NATIVE=OFF) against a scalar step written here from the
// same host-device functions: the same Philox words per particle, Box-Muller
// with the standard library's log, cos and sin, and the same update. Only
// the float transcendental functions differ (vector versions of a few ulp
// against correctly rounded ones, ~1e-7 relative), so every particle must
// agree to 1e-6 of its noise term; a wrong counter, key, component or
// block boundary would be off by the whole noise term.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/core/stream_ids.hpp"
#include "systems/sde/gaussian_noise.hpp"
#include "systems/sde/sde_kernel.hpp"

namespace granflow::sde {
namespace {

// Normal number `component` of particle `item` at this step, without vector code.
float scalar_noise(const StepInput& in, std::uint64_t item, int component) {
  std::uint32_t c0 = static_cast<std::uint32_t>(item), c1 = static_cast<std::uint32_t>(item >> 32);
  std::uint32_t c2 = static_cast<std::uint32_t>(in.step), c3 = stream::sde_noise << 16;
  philox4x32_10(c0, c1, c2, c3, static_cast<std::uint32_t>(in.seed), static_cast<std::uint32_t>(in.seed >> 32));
  const std::uint32_t words[4] = {c0, c1, c2, c3};
  const int pair = component / 2;
  const float radius = box_muller_radius(words[2 * pair]);
  const float angle = box_muller_angle(words[2 * pair + 1]);
  return component % 2 == 0 ? radius * std::cos(angle) : radius * std::sin(angle);
}

template <int D>
void expect_kernel_matches_scalar(Scheme scheme, double tau0) {
  constexpr std::size_t count = 1000;  // several 256-particle blocks and a partial one
  SdeModel model;
  model.gamma0 = 2.0;
  model.diffusivity0 = 0.3;
  model.tau0 = tau0;
  const StepInput in{model, scheme, 1.5, 0.01, 0x123456789abcdefull, 42};
  std::vector<double> x(count * D), v(count * D);
  for (std::size_t k = 0; k < x.size(); ++k) {
    x[k] = 0.001 * static_cast<double>(k);
    v[k] = std::sin(static_cast<double>(k));
  }
  std::vector<double> x_fast = x, v_fast = v;
  sde_step_range<D>(x_fast.data(), v_fast.data(), 0, count, in);

  const OrnsteinUhlenbeck ou = exact_velocity_update(model, in.time, in.dt);
  double worst = 0.0;
  for (std::size_t i = 0; i < count; ++i)
    for (int a = 0; a < D; ++a) {
      const std::size_t k = i * D + a;
      double xs = x[k], vs = v[k];
      const float noise = scalar_noise(in, i, a);
      if (scheme == Scheme::euler_maruyama)
        euler_maruyama_step(xs, vs, model.friction(in.time), model.diffusivity(in.time), in.dt, noise);
      else
        drift_ou_drift_step(xs, vs, ou, in.dt, noise);
      // The size of this particle's noise term: the same step with no noise.
      double xq = x[k], vq = v[k];
      if (scheme == Scheme::euler_maruyama)
        euler_maruyama_step(xq, vq, model.friction(in.time), model.diffusivity(in.time), in.dt, 0.0f);
      else
        drift_ou_drift_step(xq, vq, ou, in.dt, 0.0f);
      const double scale = std::abs(vs - vq) + 1e-300;
      ASSERT_LE(std::abs(v_fast[k] - vs), 1e-6 * scale + 1e-15) << "particle " << i << " component " << a;
      ASSERT_LE(std::abs(x_fast[k] - xs), 1e-6 * std::abs(xs - xq) + 1e-15) << "particle " << i << " component " << a;
      worst = std::max(worst, std::abs(v_fast[k] - vs) / scale);
    }
  std::printf("%dD: largest relative difference of the noise term %.2e\n", D, worst);
}

TEST(SdeKernel, VectorisedExactOuStepMatchesScalarStep) {
  expect_kernel_matches_scalar<1>(Scheme::exact_ou, 1.0);
  expect_kernel_matches_scalar<2>(Scheme::exact_ou, INFINITY);
  expect_kernel_matches_scalar<3>(Scheme::exact_ou, 1.0);
}

TEST(SdeKernel, VectorisedEulerMaruyamaStepMatchesScalarStep) {
  expect_kernel_matches_scalar<2>(Scheme::euler_maruyama, 1.0);
  expect_kernel_matches_scalar<3>(Scheme::euler_maruyama, INFINITY);
}

}  // namespace
}  // namespace granflow::sde
