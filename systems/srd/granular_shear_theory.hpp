#pragma once
// Kinetic (streaming) viscosity and steady shear temperature of granular SRD,
// derived as Kikuchi et al. (2003) derive the elastic viscosity, with the
// granular collision operator in place of the rotation (docs/srd.md, "Granular
// SRD under shear", has the derivation).
//
// Streaming builds the correlation <v_x v_y> up by -gamma_dot dt <v_y^2> per
// step; a collision multiplies it by h, the mean over the particle's cell of
//   h_n = 1/n + (n - 1)/n g(eps_n),
// with n the cell's occupation (the particle's share of a Poisson cell,
// n P(n) / n0) and g the factor by which the operator keeps the traceless part
// of the correlation, averaged over its random axes:
//   rotation only          2D cos 2a; 3D c3 = (1 + 2 cos a + 2 cos 2a) / 5
//   whole / 2D             eps^2 c_D
//   3D rotated plane       2/15 + (2/5) eps cos a + eps^2 (12 cos^2 a - 5) / 15
//   random axis            c_D (1 - 2 s / D + q_D s^2), s = 1 - eps, q_2 = 1/4, q_3 = 2/15
// The balance of the two gives nu_kin = (kT dt / m) (1 / (1 - h) - 1/2), which
// at eps = 1 is Kikuchi's formula. eps_n = 1 - n (1 - eps^2) sigma^2 dt
// sqrt(theta_n) (systems/srd/srd_kernels.hpp) depends on the cell's thermal
// temperature theta_n, distributed as kT chi^2_k / (D n), k = D (n - 1);
// h takes its exact mean over that distribution and the occupation, assuming,
// as the derivation does, molecular chaos and eps_n > 0.
//
// Dissipation: a collision removes the share phi (1 - eps_n^2) of a cell's
// thermal energy (D/2) n theta_n (phi as in srd_theory.hpp). Under steady
// shear the viscous heating per particle, m (nu_kin + nu_coll) gamma_dot^2,
// balances it at one temperature.

#include <cmath>
#include <numbers>

#include "systems/srd/srd_kernels.hpp"
#include "systems/srd/srd_theory.hpp"

namespace granflow::srd {

struct GranularShearParameters {
  int dimension = 2;
  Dissipation rule = Dissipation::rotated_plane;
  double n0 = 10.0;           // particles per cell
  double alpha = 0.0;         // rotation angle, radians
  double dt = 1.0;
  double restitution = 1.0;   // eps of the collision rule
  double diameter = 0.0;      // sigma, in cell sizes
  double mass = 1.0;
};

namespace detail {

// Moments of theta_n / kT: E[theta^(p/2)] for chi^2_k / (D n).
inline double theta_moment(int dimension, double n, double half_powers) {
  const double k = dimension * (n - 1.0);
  const double p = half_powers / 2.0;
  return std::exp(std::lgamma(k / 2.0 + p) - std::lgamma(k / 2.0)) * std::pow(2.0 / (dimension * n), p);
}

// The Poisson occupations worth summing (the rest weighs below 1e-16).
inline int largest_occupation(double n0) { return static_cast<int>(n0 + 12.0 * std::sqrt(n0) + 40.0); }

inline double poisson(double n0, int n) { return std::exp(n * std::log(n0) - n0 - std::lgamma(n + 1.0)); }

}  // namespace detail

// g = g0 + g1 eps + g2 eps^2 of the rule (above).
struct CorrelationFactor {
  double g0 = 0, g1 = 0, g2 = 0;
};
inline CorrelationFactor correlation_factor(int dimension, Dissipation rule, double alpha) {
  const double c = std::cos(alpha);
  const double rotation = dimension == 2 ? std::cos(2.0 * alpha) : (1.0 + 2.0 * c + 2.0 * std::cos(2.0 * alpha)) / 5.0;
  if (rule == Dissipation::random_axis) {
    const double D = dimension, q = dimension == 2 ? 0.25 : 2.0 / 15.0;
    return {rotation * (1.0 - 2.0 / D + q), rotation * (2.0 / D - 2.0 * q), rotation * q};
  }
  if (rule == Dissipation::whole || dimension == 2) return {0.0, 0.0, rotation};
  return {2.0 / 15.0, 0.4 * c, (12.0 * c * c - 5.0) / 15.0};
}

// h_n: the factor by which the collision of a cell of n keeps a member's
// <v_x v_y>, at thermal temperature kT.
inline double correlation_kept_in_cell(const GranularShearParameters& p, int n, double temperature) {
  if (n < 2) return 1.0;
  const CorrelationFactor g = correlation_factor(p.dimension, p.rule, p.alpha);
  const double rate = (1.0 - p.restitution * p.restitution) * p.diameter * p.diameter * p.dt;
  // eps_n = 1 - n rate sqrt(theta_n): its mean and mean square.
  const double mean_root = std::sqrt(temperature) * detail::theta_moment(p.dimension, n, 1.0);
  const double mean_theta = temperature * (n - 1.0) / n;
  const double eps = 1.0 - n * rate * mean_root;
  const double eps2 = 1.0 - 2.0 * n * rate * mean_root + n * n * rate * rate * mean_theta;
  return 1.0 / n + (n - 1.0) / n * (g.g0 + g.g1 * eps + g.g2 * eps2);
}

// h: the same for a particle of the Poisson fluid (its cell holds n with
// probability n P(n) / n0).
inline double correlation_kept(const GranularShearParameters& p, double temperature) {
  double h = 0.0;
  for (int n = 1; n <= detail::largest_occupation(p.n0); ++n)
    h += n * detail::poisson(p.n0, n) / p.n0 * correlation_kept_in_cell(p, n, temperature);
  return h;
}

// Kinetic viscosity nu_kin (kinematic, L^2/T) at thermal temperature kT.
inline double granular_kinetic_viscosity(const GranularShearParameters& p, double temperature) {
  return temperature * p.dt / p.mass * (1.0 / (1.0 - correlation_kept(p, temperature)) - 0.5);
}

// Thermal energy a collision removes per particle per unit time at kT.
inline double granular_dissipation_rate(const GranularShearParameters& p, double temperature) {
  const double rate = (1.0 - p.restitution * p.restitution) * p.diameter * p.diameter * p.dt;
  if (rate == 0.0) return 0.0;
  const double phi = dissipated_share(p.dimension, p.rule);
  double loss = 0.0;
  for (int n = 2; n <= detail::largest_occupation(p.n0); ++n) {
    // E[theta (1 - eps_n^2)] = 2 n rate E[theta^3/2] - n^2 rate^2 E[theta^2].
    const double theta_3_2 = std::pow(temperature, 1.5) * detail::theta_moment(p.dimension, n, 3.0);
    const double theta_2 = temperature * temperature * detail::theta_moment(p.dimension, n, 4.0);
    const double per_cell = phi * 0.5 * p.dimension * n * (2.0 * n * rate * theta_3_2 - n * n * rate * rate * theta_2);
    loss += detail::poisson(p.n0, n) * per_cell / p.n0;
  }
  return loss / p.dt;
}

// The temperature at which the viscous heating at shear rate gamma_dot
// (kinetic viscosity at that temperature plus `collisional`) equals the
// dissipation; nan where none does while eps_n > 0 in typical cells.
inline double steady_shear_temperature(const GranularShearParameters& p, double shear_rate, double collisional) {
  const double rate = (1.0 - p.restitution * p.restitution) * p.diameter * p.diameter * p.dt;
  if (rate == 0.0 || shear_rate == 0.0) return std::nan("");
  const auto excess = [&](double t) {
    return granular_dissipation_rate(p, t) -
           p.mass * (granular_kinetic_viscosity(p, t) + collisional) * shear_rate * shear_rate;
  };
  // eps_n stays above 0 for the typical cell (n0 + 3 sqrt n0) below this.
  const double highest = std::pow(0.5 / ((p.n0 + 3.0 * std::sqrt(p.n0)) * rate), 2.0);
  double low = highest * 1e-16, high = highest;
  if (excess(low) > 0.0 || excess(high) < 0.0) return std::nan("");
  for (int k = 0; k < 200; ++k) {
    const double middle = std::sqrt(low * high);
    (excess(middle) < 0.0 ? low : high) = middle;
  }
  return std::sqrt(low * high);
}

}  // namespace granflow::srd
