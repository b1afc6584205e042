#pragma once
// Hard-sphere kinematics shared by the fast engine, the reference engine and
// (later) device code: time to contact, the smooth inelastic pair collision
// with a constant normal restitution (Brilliantov & Poeschel 2004;
// Poeschel & Schwager 2005) and the wall reflection.

#include <cmath>
#include <limits>

#include "components/vector.hpp"
#include "engine/core/host_device.hpp"

namespace granflow::edmd {

inline constexpr double never = std::numeric_limits<double>::infinity();

// Time until two spheres with separation dx = x_j - x_i and relative velocity
// dv = v_j - v_i touch at distance sigma. Pairs that already overlap by
// round-off while approaching collide at once (Bannerman et al. 2013), so an
// overlap can never let a pair pass through each other; receding pairs never
// collide. The root is taken in the cancellation-free form.
template <int D>
GRANFLOW_HD inline double contact_time(const Vec<D>& dx, const Vec<D>& dv, double sigma) {
  const double b = dx.dot(dv);
  if (b >= 0.0) return never;
  const double gap = dx.squaredNorm() - sigma * sigma;
  if (gap <= 0.0) return 0.0;
  const double dv2 = dv.squaredNorm();
  const double discriminant = b * b - dv2 * gap;
  if (discriminant <= 0.0) return never;
  return gap / (-b + std::sqrt(discriminant));
}

struct PairCollisionResult {
  double dissipated_energy;  // (1 - xi^2) mu v_n^2 / 2
  double virial;             // r_ij . delta p_i, for the collisional pressure
};

// Smooth inelastic collision of i and j in contact with separation dx = x_j - x_i.
template <int D>
GRANFLOW_HD inline PairCollisionResult collide_pair(Vec<D>& vi, Vec<D>& vj, double mi, double mj, const Vec<D>& dx,
                                                    double restitution) {
  const Vec<D> dv = vj - vi;
  const double dx2 = dx.squaredNorm();
  const double b = dv.dot(dx);
  const double total_mass = mi + mj;
  const double factor = (1.0 + restitution) * b / dx2;
  vi += (factor * mj / total_mass) * dx;
  vj -= (factor * mi / total_mass) * dx;
  const double reduced_mass = mi * mj / total_mass;
  return {0.5 * (1.0 - restitution * restitution) * reduced_mass * b * b / dx2,
          -(1.0 + restitution) * reduced_mass * b};
}

// Wall on `axis`: the normal component reverses and every component is
// multiplied by the wall restitution, which keeps the law of reflection for inelastic walls and
// brings a particle to rest for restitution 0.
template <int D>
GRANFLOW_HD inline double reflect_from_wall(Vec<D>& v, double mass, int axis, double restitution) {
  const double before = v.squaredNorm();
  v[axis] = -v[axis];
  v *= restitution;
  return 0.5 * mass * (before - v.squaredNorm());
}

}  // namespace granflow::edmd
