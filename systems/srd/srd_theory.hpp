#pragma once
// Transport coefficients of standard SRD and the cooling of granular SRD.
//   Kinetic (streaming) viscosity, Kikuchi et al. 2003, with n0 particles per
//   cell, rotation angle alpha, f = n0 - 1 + exp(-n0):
//     2D: nu_kin = (kT dt / m) [ n0 / (f (1 - cos 2 alpha)) - 1/2 ]
//     3D: nu_kin = (kT dt / m) [ 5 n0 / (f (4 - 2 cos alpha - 2 cos 2 alpha)) - 1/2 ]
//   Collisional viscosity (cell size a = 1):
//     2D: nu_coll = (1 / (12 dt)) (1 - cos alpha) f / n0
//     3D: nu_coll = (1 / (18 dt)) (1 - cos alpha) f / n0
//   Granular SRD in the homogeneous cooling state: a cell's thermal energy
//   loses the fraction 2 phi (1 - eps_eff) per step, phi the share of the
//   thermal components the rule dissipates (rotated plane: 2/3 in 3D, 1 in
//   2D; whole: 1; random axis: 1/D), so dT/dt = -2 phi (1 - eps^2) sigma^2
//   rho T^{3/2}, which is Haff's law T = T0 / (1 + t/tau)^2 with
//   1/tau = phi (1 - eps^2) sigma^2 rho sqrt(T0 / m).

#include <cmath>

#include "systems/srd/srd_kernels.hpp"

namespace granflow::srd {

inline double collision_factor(double n0) { return n0 - 1.0 + std::exp(-n0); }

inline double kinetic_viscosity(int dimension, double n0, double alpha, double temperature, double dt, double mass = 1.0) {
  const double f = collision_factor(n0);
  const double bracket = dimension == 2 ? n0 / (f * (1.0 - std::cos(2.0 * alpha))) - 0.5
                                        : 5.0 * n0 / (f * (4.0 - 2.0 * std::cos(alpha) - 2.0 * std::cos(2.0 * alpha))) - 0.5;
  return temperature * dt / mass * bracket;
}

inline double collisional_viscosity(int dimension, double n0, double alpha, double dt) {
  return (1.0 - std::cos(alpha)) * collision_factor(n0) / n0 / ((dimension == 2 ? 12.0 : 18.0) * dt);
}

inline double dissipated_share(int dimension, Dissipation rule) {
  switch (rule) {
    case Dissipation::whole: return 1.0;
    case Dissipation::random_axis: return 1.0 / dimension;
    case Dissipation::rotated_plane: break;
  }
  return dimension == 2 ? 1.0 : 2.0 / 3.0;
}

// Haff's time of granular SRD at density rho (particles per cell).
inline double gsrd_haff_time(int dimension, Dissipation rule, double restitution, double diameter, double rho,
                             double temperature0, double mass = 1.0) {
  const double rate = dissipated_share(dimension, rule) * (1.0 - restitution * restitution) * diameter * diameter * rho *
                      std::sqrt(temperature0 / mass);
  return rate > 0 ? 1.0 / rate : INFINITY;
}

}  // namespace granflow::srd
