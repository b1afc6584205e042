#pragma once
// Kinetic theory of hard spheres (D = 3) and disks (D = 2) used to check and
// label simulations; see REFERENCE.md. k_B = 1, sigma = 2r.

#include <cmath>
#include <numbers>

#include "systems/edmd/viscoelastic_restitution.hpp"

namespace granflow::theory {

// Packing fraction of N spheres/disks of radius r in volume V.
template <int D>
double packing_fraction(double count, double radius, double volume) {
  const double one = D == 3 ? 4.0 / 3.0 * std::numbers::pi * radius * radius * radius
                            : std::numbers::pi * radius * radius;
  return count * one / volume;
}

// Radius at which N equal spheres/disks fill `eta` of the volume (area).
template <int D>
double radius_for_packing_fraction(double count, double eta, double volume) {
  const double per_particle = eta * volume / count;
  return D == 3 ? std::cbrt(per_particle * 3.0 / (4.0 * std::numbers::pi)) : std::sqrt(per_particle / std::numbers::pi);
}

// Pair correlation at contact: Carnahan-Starling (3D), Henderson (2D).
template <int D>
double contact_value(double eta) {
  if constexpr (D == 3)
    return (2.0 - eta) / (2.0 * std::pow(1.0 - eta, 3));
  else
    return (1.0 - 7.0 * eta / 16.0) / ((1.0 - eta) * (1.0 - eta));
}

// Enskog collision frequency per particle at temperature T.
template <int D>
double collision_frequency(double number_density, double diameter, double temperature, double mass, double eta) {
  const double g2 = contact_value<D>(eta);
  const double thermal = std::sqrt(temperature / mass);
  if constexpr (D == 3)
    return 4.0 * std::sqrt(std::numbers::pi) * g2 * number_density * diameter * diameter * thermal;
  else
    return 2.0 * std::sqrt(std::numbers::pi) * g2 * number_density * diameter * thermal;
}

// Haff's characteristic time: 1/tau0 = (1 - xi^2) omega(T0) / (2 d), with omega
// the Enskog collision frequency (Haff 1983; Brilliantov & Poeschel 2004).
template <int D>
double haff_time(double restitution, double collision_frequency_at_t0) {
  const double rate = (1.0 - restitution * restitution) * collision_frequency_at_t0 / (2.0 * D);
  return rate > 0.0 ? 1.0 / rate : INFINITY;
}

// Haff's law T(t)/T0 = 1 / (1 + t/tau0)^2 (Haff 1983).
inline double haff_temperature_ratio(double t, double tau0) {
  const double s = 1.0 + t / tau0;
  return 1.0 / (s * s);
}

// Haff's law of viscoelastic spheres (Brilliantov & Poeschel 2000; to first
// order in (g / g_ve)^1/5): with eps(g) = 1 - C1 (g/g_ve)^1/5 the energy lost
// per collision, averaged over the Maxwellian flux of normal impact speeds
// (variance 2T/m), makes 1 - eps^2 effectively C1 2^1.1 Gamma(2.1)
// (2T / (m g_ve^2))^1/10, so dT/dt = -(1 - eps^2)_eff omega(T) T / d. Its
// solution is T/T0 = (1 + t/tau)^-5/3 with
//   1/tau = (3/5) C1 2^1.1 Gamma(2.1) (2 T0 / (m g_ve^2))^1/10 omega(T0) / d.
template <int D>
double viscoelastic_haff_time(double viscoelastic_speed, double temperature0, double mass,
                              double collision_frequency_at_t0) {
  const double loss = edmd::viscoelastic_c1() * std::pow(2.0, 1.1) * std::tgamma(2.1) *
                      std::pow(2.0 * temperature0 / (mass * viscoelastic_speed * viscoelastic_speed), 0.1);
  return 1.0 / (0.6 * loss * collision_frequency_at_t0 / D);
}

// T(t)/T0 = (1 + t/tau)^-5/3 of viscoelastic spheres.
inline double viscoelastic_haff_temperature_ratio(double t, double tau) { return std::pow(1.0 + t / tau, -5.0 / 3.0); }

}  // namespace granflow::theory
