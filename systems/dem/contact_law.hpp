#pragma once
// The normal force of two soft spheres in contact (or a sphere and a wall),
// as functions of one contact, shared by the CPU systems and a later GPU
// port. delta > 0 is the overlap, rate its growth d delta / dt, m_eff the
// reduced mass (m for a wall). The force is repulsive when positive.
//
// Linear spring-dashpot (LSD): F = k delta + gamma rate with
// gamma = 2 sqrt(m_eff k) (-ln e) / sqrt(pi^2 + ln^2 e), which gives the
// restitution e and the contact time t_c = pi / sqrt(k / m_eff - (gamma /
// 2 m_eff)^2) of an isolated head-on collision (e.g. Schwager & Poeschel
// 2007). Convention: the contact lasts while the spheres overlap, and the
// force is not clipped at zero, so near the end of a strongly damped
// contact it is briefly attractive; e and t_c above belong to this
// convention (LAMMPS's gran/hooke does the same by default).
//
// Hertz with Kuwabara-Kono damping: F = k delta^{3/2} + (3/2) A k
// sqrt(delta) rate (Brilliantov et al. 1996), the restitution then falls
// with the impact speed; A is the damping time.

#include <cmath>
#include <numbers>

#include "engine/core/host_device.hpp"

namespace granflow::dem {

enum class ContactModel : int { lsd = 0, hertz = 1 };

struct ContactLaw {
  ContactModel model = ContactModel::lsd;
  double stiffness = 1e4;
  // LSD: gamma / sqrt(m_eff k) from the restitution; Hertz: the damping time A.
  double damping = 0.0;

  GRANFLOW_HD static double lsd_damping_factor(double restitution) {
    if (restitution >= 1.0) return 0.0;
    const double l = std::log(restitution);
    return 2.0 * (-l) / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
  }
  GRANFLOW_HD double gamma(double m_eff) const { return damping * std::sqrt(m_eff * stiffness); }
  // The contact time of an isolated LSD collision.
  GRANFLOW_HD double contact_time(double m_eff) const {
    const double eta = gamma(m_eff) / (2.0 * m_eff);
    return std::numbers::pi / std::sqrt(stiffness / m_eff - eta * eta);
  }

  struct Result {
    double force;      // along the normal, repulsive positive
    double elastic;    // stored energy
    double dissipated; // power the damping takes, >= 0
  };
  GRANFLOW_HD Result normal(double delta, double rate, double m_eff) const {
    if (model == ContactModel::lsd) return lsd(delta, rate, gamma(m_eff));
    return hertz(delta, rate);
  }
  // The spring-dashpot with its dashpot constant g = gamma(m_eff) given
  // (computed once where every contact has the same reduced mass).
  GRANFLOW_HD Result lsd(double delta, double rate, double g) const {
    return {stiffness * delta + g * rate, 0.5 * stiffness * delta * delta, g * rate * rate};
  }
  // The normal stiffness and dashpot constant at overlap delta, which the
  // tangential spring scales with (Hertz: both grow as sqrt(delta)).
  GRANFLOW_HD double normal_stiffness(double delta) const {
    return model == ContactModel::lsd ? stiffness : stiffness * std::sqrt(delta);
  }
  GRANFLOW_HD double normal_damping(double delta, double m_eff) const {
    return model == ContactModel::lsd ? gamma(m_eff) : hertz_damping(std::sqrt(delta));
  }
  GRANFLOW_HD double hertz_damping(double root_delta) const { return 1.5 * damping * stiffness * root_delta; }
  GRANFLOW_HD Result hertz(double delta, double rate) const {
    const double root = std::sqrt(delta);
    const double g = hertz_damping(root);
    return {stiffness * delta * root + g * rate, 0.4 * stiffness * delta * delta * root, g * rate * rate};
  }
};

}  // namespace granflow::dem
