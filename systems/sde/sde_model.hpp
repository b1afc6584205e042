#pragma once
// Underdamped Langevin dynamics and underdamped scaled Brownian motion
// (UDSBM; Bodrova et al. 2016), per Cartesian component:
//   dx = v dt,  dv = -gamma(t) v dt + sqrt(2 D(t)) gamma(t) dW,
// with gamma = gamma0 / (1 + t/tau0), D = D0 / (1 + t/tau0) for UDSBM and
// tau0 = inf (constant coefficients) for Langevin. The fluctuation-
// dissipation relation D = T/(m gamma) fixes the noise (fluctuation-dissipation).
//
// The step functions are GRANFLOW_HD so CPU and CUDA share them.

#include <cmath>
#include <limits>

#include "engine/core/host_device.hpp"

namespace granflow::sde {

struct SdeModel {
  double gamma0 = 1.0;
  double diffusivity0 = 1.0;
  double tau0 = std::numeric_limits<double>::infinity();  // inf: Langevin

  GRANFLOW_HD bool scaled() const { return tau0 < std::numeric_limits<double>::infinity(); }
  GRANFLOW_HD double decay(double t) const { return scaled() ? 1.0 / (1.0 + t / tau0) : 1.0; }
  GRANFLOW_HD double friction(double t) const { return gamma0 * decay(t); }
  GRANFLOW_HD double diffusivity(double t) const { return diffusivity0 * decay(t); }
  // Velocity variance per component that the noise sustains at time t:
  // T/m = D0 gamma0 for Langevin, D0 gamma0 k/(k-1) / (1 + t/tau0)^2 for UDSBM (k = gamma0 tau0).
  GRANFLOW_HD double stationary_velocity_variance(double t = 0.0) const {
    if (!scaled()) return diffusivity0 * gamma0;
    const double k = gamma0 * tau0;
    const double u = 1.0 + t / tau0;
    return diffusivity0 * gamma0 * k / (k - 1.0) / (u * u);
  }
};

// Euler-Maruyama's velocity update v <- (1 - gamma dt) v + noise amplifies
// v wherever gamma(t) dt >= 2 (|1 - gamma dt| >= 1): the time until which
// that holds, 0 where it never does, infinity where it always does
// (Langevin). gamma(t) = gamma0 / (1 + t / tau0) falls below 2 / dt at
// t = tau0 (gamma0 dt / 2 - 1).
inline double euler_maruyama_unstable_until(const SdeModel& m, double dt) {
  if (!(m.gamma0 * dt >= 2.0)) return 0.0;
  if (!m.scaled()) return std::numeric_limits<double>::infinity();
  return m.tau0 * (0.5 * m.gamma0 * dt - 1.0);
}

// Exact Ornstein-Uhlenbeck update of the velocity over [t, t + h]:
// v <- decay * v + spread * N(0, 1), with decay = exp(-int gamma) and
// spread^2 = int 2 D gamma^2 exp(-2 int_s gamma) ds.
struct OrnsteinUhlenbeck {
  double decay;
  double spread;
};

GRANFLOW_HD inline OrnsteinUhlenbeck exact_velocity_update(const SdeModel& m, double t, double h) {
  if (!m.scaled()) {
    const double decay = std::exp(-m.gamma0 * h);
    return {decay, std::sqrt(m.diffusivity0 * m.gamma0 * (1.0 - decay * decay))};
  }
  const double k = m.gamma0 * m.tau0;
  const double u0 = 1.0 + t / m.tau0, u1 = 1.0 + (t + h) / m.tau0;
  const double log_ratio = std::log(u0 / u1);  // < 0
  const double decay = std::exp(k * log_ratio);
  // (1 - (u0/u1)^(2k-2)) / (k - 1), continuous through k = 1.
  const double km1 = k - 1.0;
  const double bracket = std::abs(km1) > 1e-12 ? -std::expm1(2.0 * km1 * log_ratio) / km1 : -2.0 * log_ratio;
  const double variance = m.diffusivity0 * m.gamma0 * k / (u1 * u1) * bracket;
  return {decay, std::sqrt(std::max(variance, 0.0))};
}

// Euler-Maruyama (Kloeden & Platen 1992), for one component:
// x += v h;  v += -gamma v h + sqrt(2 D) gamma sqrt(h) N.
GRANFLOW_HD inline void euler_maruyama_step(double& x, double& v, double gamma, double diffusivity, double h,
                                            double normal) {
  const double v_old = v;
  v = v_old - gamma * v_old * h + std::sqrt(2.0 * diffusivity * h) * gamma * normal;
  x += v_old * h;
}

// BAOAB-style splitting without forces: half drift, exact OU, half drift.
GRANFLOW_HD inline void drift_ou_drift_step(double& x, double& v, const OrnsteinUhlenbeck& ou, double h,
                                            double normal) {
  x += 0.5 * h * v;
  v = ou.decay * v + ou.spread * normal;
  x += 0.5 * h * v;
}

}  // namespace granflow::sde
