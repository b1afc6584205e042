#pragma once
// Tangential friction of one contact with history (Cundall & Strack 1979):
// a spring along the tangent plane, stretched by the relative velocity of
// the contact points while the surfaces touch, with a dashpot, capped by
// Coulomb's limit mu F_n; when the cap acts the contact slides and the
// spring is shortened to what the capped force needs (the convention of
// LAMMPS's gran/hooke/history). As one function of one contact, shared by
// the CPU systems and a later GPU port.
//
// Before the spring is stretched its stored displacement is turned into the
// current tangent plane (keeping its length), so a contact rolling round a
// sphere neither gains nor loses elastic energy by the rotation of the
// normal.

#include <cmath>

#include "engine/core/host_device.hpp"
#include "systems/dem/neighbour_list.hpp"

namespace granflow::dem {

struct TangentialFriction {
  double mu = 0.0;                       // Coulomb coefficient; 0: frictionless
  double stiffness_ratio = 2.0 / 7.0;    // k_t / k_n (for Hertz: of k_n sqrt(delta))
  double damping_ratio = 0.5;            // gamma_t / gamma_n
  double dt = 0.0;                       // the step the spring is stretched over

  bool active() const { return mu > 0.0; }

  struct Result {
    double force[3];    // on the first body's contact point
    double elastic;     // energy in the spring after this step
    double dissipated;  // power the dashpot and the sliding took over this step, >= 0 up to round-off
  };

  // xi: the contact's spring (updated); contact_velocity: the first body's
  // contact point relative to the second's; normal: unit, from the second
  // body to the first; normal_force: F_n (repulsive positive); k_n and
  // gamma_n: the normal spring's stiffness and dashpot constant at this
  // overlap.
  GRANFLOW_HD Result apply(Shear& xi, const double* contact_velocity, const double* normal, double normal_force,
                           double k_n, double gamma_n) const {
    const double k_t = stiffness_ratio * k_n, gamma_t = damping_ratio * gamma_n;
    const double* n = normal;
    const double vn = contact_velocity[0] * n[0] + contact_velocity[1] * n[1] + contact_velocity[2] * n[2];
    double vt[3], along = xi[0] * n[0] + xi[1] * n[1] + xi[2] * n[2];
    const double length2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
    for (int a = 0; a < 3; ++a) {
      vt[a] = contact_velocity[a] - vn * n[a];
      xi[a] -= along * n[a];
    }
    const double projected2 = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
    if (projected2 > 0.0) {
      const double keep = std::sqrt(length2 / projected2);
      for (double& c : xi) c *= keep;
    }
    const double before = 0.5 * k_t * length2;
    Result r{};
    double f2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      xi[a] += vt[a] * dt;
      r.force[a] = -k_t * xi[a] - gamma_t * vt[a];
      f2 += r.force[a] * r.force[a];
    }
    const double limit = mu * (normal_force > 0.0 ? normal_force : 0.0);
    if (f2 > limit * limit) {
      const double scale = f2 > 0.0 ? limit / std::sqrt(f2) : 0.0;
      for (int a = 0; a < 3; ++a) {
        r.force[a] *= scale;
        xi[a] = k_t > 0.0 ? -(r.force[a] + gamma_t * vt[a]) / k_t : 0.0;
      }
    }
    r.elastic = 0.5 * k_t * (xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]);
    const double power = r.force[0] * vt[0] + r.force[1] * vt[1] + r.force[2] * vt[2];
    r.dissipated = dt > 0.0 ? -power - (r.elastic - before) / dt : 0.0;
    return r;
  }
};

}  // namespace granflow::dem
