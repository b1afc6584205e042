#pragma once
// The time scales a soft-sphere time step must resolve, worked out before
// the run for every contact the run can have (sphere pairs and each wall,
// linear spring-dashpot or Hertz), and what they allow.
//
// Per contact of reduced mass m_eff (m / 2 for a pair of equal spheres, m
// for a sphere on a wall):
//  - the spring time pi / omega, half an undamped period at the stiffest
//    point of the contact (Hertz: omega^2 = (3/2) k sqrt(delta) / m_eff at
//    the largest overlap the energy allows). Velocity Verlet is unstable
//    for omega dt > 2; above omega dt ~ 1 the rebound is already wrong, so
//    dt > spring / 3 is refused and dt > spring / 10 warned about;
//  - the damping time m_eff / gamma in which the dashpot relaxes a
//    relative speed: an explicit step with gamma dt / m_eff > 2 amplifies
//    it instead, so dt > damping time is refused, dt > damping / 5 warned;
//  - the duration of an isolated collision (LSD: t_c; Hertz: 2.94 delta /
//    v, e.g. Poeschel & Schwager 2005), the default step being a fiftieth
//    of it;
//  - the largest overlap: LSD v / omega (undamped, an upper bound), Hertz
//    (5 m_eff v^2 / 4 k)^(2/5), or the overlap under the load of a column
//    of spheres at rest, whichever is larger. A sphere overlapping by its
//    radius passes through a wall or sits on another's centre.
// v is the fastest relative speed the run can be expected to see: twice
// the fastest initial speed, twice the fastest wall speed, and the speed
// of a fall through the height of the bed.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "systems/dem/contact_law.hpp"

namespace granflow::dem {

struct ContactScales {
  double spring_time = 0.0;
  double damping_time = std::numeric_limits<double>::infinity();
  double duration = 0.0;
  double overlap = 0.0;
  bool overdamped = false;  // LSD: the spheres never separate (no duration)

  double shortest() const { return std::min(spring_time, damping_time); }
  // The default step: a fiftieth of the collision, or less where the dashpot is faster.
  double default_step() const { return std::min(duration, 5.0 * damping_time) / 50.0; }
  // The largest step that still resolves the contact.
  double largest_step() const { return std::min(spring_time / 3.0, damping_time); }
};

// `speed`: the relative speed of the contact; `load`: the force it carries at rest.
inline ContactScales contact_scales(const ContactLaw& law, double m_eff, double speed, double load) {
  ContactScales s;
  const double k = law.stiffness;
  if (law.model == ContactModel::lsd) {
    const double omega = std::sqrt(k / m_eff);
    const double gamma = law.gamma(m_eff);
    const double eta = gamma / (2.0 * m_eff);
    s.spring_time = std::numbers::pi / omega;
    if (gamma > 0.0) s.damping_time = m_eff / gamma;
    s.overdamped = eta >= omega;
    s.duration = s.overdamped ? std::numeric_limits<double>::infinity() : law.contact_time(m_eff);
    s.overlap = std::max(speed / omega, load / k);
    return s;
  }
  const double kinetic = std::pow(1.25 * m_eff * speed * speed / k, 0.4);
  s.overlap = std::max(kinetic, std::pow(load / k, 2.0 / 3.0));
  const double root = std::sqrt(s.overlap);
  const double omega = std::sqrt(1.5 * k * root / m_eff);
  s.spring_time = std::numbers::pi / omega;
  const double gamma = 1.5 * law.damping * k * root;
  if (gamma > 0.0) s.damping_time = m_eff / gamma;
  s.duration = speed > 0.0 ? 2.94 * kinetic / speed : s.spring_time;
  return s;
}

inline bool usable_time(double t) { return std::isfinite(t) && t > 0.0; }

}  // namespace granflow::dem
