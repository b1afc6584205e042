#pragma once
// Theory of the ensemble MSD of Langevin dynamics and UDSBM, per Cartesian
// component: the closed forms for stationary initial velocities (Langevin;
// UDSBM: Bodrova et al. 2016) and, for any initial velocity variance, the
// exact second-moment equations
//   d<x^2>/dt = 2 <xv>,  d<xv>/dt = <v^2> - gamma <xv>,
//   d<v^2>/dt = -2 gamma <v^2> + 2 D gamma^2,
// integrated with classical Runge-Kutta on a grid fine against 1/gamma.
// Parameters of a hard-sphere gas: Haff's time (Haff 1983) and the Enskog
// self-diffusion coefficient and velocity relaxation rate of the gas
// (Brilliantov & Poeschel 2000, 2004), as UDSBM maps them (Bodrova et al. 2016).

#include <cmath>
#include <numbers>
#include <vector>

#include "systems/edmd/kinetic_theory.hpp"
#include "systems/sde/sde_model.hpp"

namespace granflow::sde {

// Langevin MSD for a stationary start: 2 D t - (2 D / gamma)(1 - e^{-gamma t}).
inline double langevin_msd(const SdeModel& m, double t) {
  return 2.0 * m.diffusivity0 * t + 2.0 * m.diffusivity0 / m.gamma0 * std::expm1(-m.gamma0 * t);
}

// UDSBM MSD for a stationary start (Bodrova et al. 2016), k = gamma0 tau0 != 1.
inline double udsbm_msd(const SdeModel& m, double t) {
  const double k = m.gamma0 * m.tau0;
  const double u = 1.0 + t / m.tau0;
  return 2.0 * m.diffusivity0 * m.tau0 * k * k / ((k - 1.0) * (k - 1.0)) *
         (std::log(u) - (1.0 - std::pow(u, 1.0 - k)) / (k - 1.0));
}

// The moment equations of Langevin dynamics (constant gamma and D) in closed
// form for any initial velocity variance v2 (A = v2 - D gamma):
//   <v^2> = D gamma + A e^{-2 gamma t},
//   <xv>  = D (1 - e^{-gamma t}) + (A / gamma)(e^{-gamma t} - e^{-2 gamma t}),
//   <x^2> = 2 D t - 2 D (1 - e^{-gamma t}) / gamma
//           + (2 A / gamma^2) [(1 - e^{-gamma t}) - (1 - e^{-2 gamma t}) / 2].
inline double langevin_moment_msd(const SdeModel& m, double v2, double t) {
  const double g = m.gamma0, d = m.diffusivity0, a = v2 - d * g;
  const double one = -std::expm1(-g * t), two = -std::expm1(-2.0 * g * t);
  return 2.0 * d * t - 2.0 * d * one / g + 2.0 * a / (g * g) * (one - 0.5 * two);
}

// Classical Runge-Kutta steps the UDSBM moment equations need up to t_stop:
// steps of 0.02 / gamma(t) grow as the friction decays.
inline double moment_msd_steps(const SdeModel& m, double t_stop) {
  return m.gamma0 * m.tau0 / 0.02 * std::log1p(t_stop / m.tau0);
}

// The moment equations integrated (any model; moment_msd_steps steps for UDSBM).
inline std::vector<double> integrated_moment_msd(const SdeModel& m, double v2, const std::vector<double>& times) {
  std::vector<double> out;
  double x2 = 0.0, xv = 0.0, vv = v2, t = 0.0;
  const auto rates = [&](double time, double b, double c, double& da, double& db, double& dc) {
    const double g = m.friction(time), d = m.diffusivity(time);
    da = 2.0 * b;
    db = c - g * b;
    dc = -2.0 * g * c + 2.0 * d * g * g;
  };
  const double h_max = 0.02 / m.gamma0;
  for (double target : times) {
    while (t < target) {
      // Steps grow with the time scale of UDSBM's decaying friction.
      const double h = std::min(target - t, h_max / m.decay(t));
      double k1[3], k2[3], k3[3], k4[3];
      rates(t, xv, vv, k1[0], k1[1], k1[2]);
      rates(t + h / 2, xv + h / 2 * k1[1], vv + h / 2 * k1[2], k2[0], k2[1], k2[2]);
      rates(t + h / 2, xv + h / 2 * k2[1], vv + h / 2 * k2[2], k3[0], k3[1], k3[2]);
      rates(t + h, xv + h * k3[1], vv + h * k3[2], k4[0], k4[1], k4[2]);
      x2 += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]);
      xv += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]);
      vv += h / 6 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2]);
      t += h;
    }
    out.push_back(x2);
  }
  return out;
}

// MSD per component at each of `times` (ascending) for initial velocity
// variance v2: closed form for Langevin, integrated for UDSBM (callers bound
// moment_msd_steps first).
inline std::vector<double> moment_msd(const SdeModel& m, double v2, const std::vector<double>& times) {
  if (m.scaled()) return integrated_moment_msd(m, v2, times);
  std::vector<double> out;
  for (double t : times) out.push_back(langevin_moment_msd(m, v2, t));
  return out;
}

// gamma0, D0 and tau0 of a 3D hard-sphere gas of N spheres of radius r and
// mass m in a box of volume V at temperature T0 with restitution xi: D0 from
// Enskog theory, gamma0 = T0 / (m D0) (fluctuation-dissipation), tau0 from Haff's law (inf at xi = 1).
inline SdeModel model_from_gas(double count, double radius, double restitution, double temperature, double mass,
                               double volume) {
  const double n = count / volume, sigma = 2.0 * radius;
  const double eta = theory::packing_fraction<3>(count, radius, volume);
  const double g2 = theory::contact_value<3>(eta);
  SdeModel m;
  m.diffusivity0 = 1.5 / (n * g2 * sigma * sigma * (1.0 + restitution) * (1.0 + restitution)) *
                   std::sqrt(temperature / (mass * std::numbers::pi));
  m.gamma0 = temperature / (mass * m.diffusivity0);
  m.tau0 = theory::haff_time<3>(restitution, theory::collision_frequency<3>(n, sigma, temperature, mass, eta));
  return m;
}

}  // namespace granflow::sde
