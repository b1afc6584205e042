#pragma once
// The physics of stochastic rotation dynamics (Malevanets & Kapral 1999) and
// its granular variant, as functions of one particle or one cell that the
// CPU systems and the CUDA kernels share: streaming with Lees-Edwards shear
// planes, the cell a shifted position falls in, the rotation of a thermal
// velocity, and the effective restitution of a cell.
//
// Conventions: cells have edge 1 (lengths are in cell sizes a), the box is
// [0, cells_a) along each axis, shear flows along axis 0 with its gradient
// along axis 1 (Lees-Edwards planes at y = 0 and y = L_y).

#include <cmath>
#include <cstdint>

#include "engine/host_device.hpp"

namespace granflow::srd {

// Lees-Edwards state: the upper image moves with +velocity (= shear rate x
// L_y) and is displaced by +offset along axis 0 (offset in [0, L_x)).
struct Shear {
  double velocity = 0.0;
  double offset = 0.0;
};

// x += v dt, then back into the box; crossing a shear plane k times moves the
// particle by -k offset along x and changes v_x by -k velocity (Lees-Edwards).
template <int D>
GRANFLOW_HD inline void stream_particle(double* x, double* v, double dt, const double* length, Shear shear) {
  for (int a = 0; a < D; ++a) x[a] += v[a] * dt;
  if (D >= 2 && shear.velocity != 0.0) {
    const double crossings = std::floor(x[1] / length[1]);
    if (crossings != 0.0) {
      x[1] -= crossings * length[1];
      x[0] -= crossings * shear.offset;
      v[0] -= crossings * shear.velocity;
    }
  }
  for (int a = 0; a < D; ++a) {
    x[a] -= std::floor(x[a] / length[a]) * length[a];
    if (x[a] >= length[a]) x[a] = 0.0;  // round-off of a value just below zero
  }
}

// Linear index of the cell holding x + shift. A shifted position beyond a
// shear plane belongs to the moving image: its x is taken back by the offset.
template <int D>
GRANFLOW_HD inline std::uint32_t cell_of(const double* x, const double* shift, const double* length,
                                         const std::int32_t* cells, Shear shear) {
  double s[D];
  for (int a = 0; a < D; ++a) s[a] = x[a] + shift[a];
  if (D >= 2 && shear.velocity != 0.0) {
    const double crossings = std::floor(s[1] / length[1]);
    s[0] -= crossings * shear.offset;
  }
  std::uint32_t index = 0;
  for (int a = D - 1; a >= 0; --a) {
    auto c = static_cast<std::int64_t>(std::floor(s[a]));
    c %= cells[a];
    if (c < 0) c += cells[a];
    index = index * static_cast<std::uint32_t>(cells[a]) + static_cast<std::uint32_t>(c);
  }
  return index;
}

// A cell that straddles a shear plane holds particles of two images: those
// whose shifted position lies beyond the plane move, seen from the cell,
// with v_x - k velocity (k = +1 above, -1 below). This is what to add to
// their v_x for the cell's mean and rotation (and subtract after it).
template <int D>
GRANFLOW_HD inline double image_velocity_x(const double* x, const double* shift, const double* length, Shear shear) {
  if (D < 2 || shear.velocity == 0.0) return 0.0;
  return -std::floor((x[1] + shift[1]) / length[1]) * shear.velocity;
}

// The granular cell's effective restitution, 1 - (1 - eps^2) sigma^2 rho
// sqrt(theta) dt, clamped to [0, 1]; `clamped` tells whether it was below 0.
GRANFLOW_HD inline double effective_restitution(double restitution, double diameter, double density, double theta,
                                                double dt, bool& clamped) {
  const double value =
      1.0 - (1.0 - restitution * restitution) * diameter * diameter * density * std::sqrt(theta > 0 ? theta : 0.0) * dt;
  clamped = value < 0.0;
  return value < 0.0 ? 0.0 : (value > 1.0 ? 1.0 : value);
}

// How the granular rule dissipates: only the rotated thermal components (the
// plane of the rotation; all components in 2D), along a random axis of the
// rotated velocity, or the whole rotated velocity.
enum class Dissipation : int { rotated_plane = 0, random_axis = 1, whole = 2 };

// One cell's collision operator: rotation by alpha (2D: sign `sign`, 3D:
// about unit `axis`), then the granular scaling by `eps` as `rule` says
// (`direction`: the unit dissipation axis of random_axis).
template <int D>
struct CellRotation {
  double cos_alpha = 1.0;
  double sin_alpha = 0.0;
  double axis[3] = {0.0, 0.0, 1.0};
  double direction[3] = {1.0, 0.0, 0.0};
  double eps = 1.0;
  Dissipation rule = Dissipation::rotated_plane;

  // u: a thermal velocity (v - V of the cell), rotated in place.
  GRANFLOW_HD void apply(double* u) const {
    double w[D];
    if constexpr (D == 2) {
      w[0] = cos_alpha * u[0] - sin_alpha * u[1];
      w[1] = sin_alpha * u[0] + cos_alpha * u[1];
      if (rule != Dissipation::random_axis) {
        w[0] *= eps;
        w[1] *= eps;
      }
    } else {
      const double along = axis[0] * u[0] + axis[1] * u[1] + axis[2] * u[2];
      double perpendicular[3], cross[3];
      for (int a = 0; a < 3; ++a) perpendicular[a] = u[a] - along * axis[a];
      cross[0] = axis[1] * perpendicular[2] - axis[2] * perpendicular[1];
      cross[1] = axis[2] * perpendicular[0] - axis[0] * perpendicular[2];
      cross[2] = axis[0] * perpendicular[1] - axis[1] * perpendicular[0];
      const double plane = rule == Dissipation::random_axis ? 1.0 : eps;
      const double axial = rule == Dissipation::whole ? eps : 1.0;
      for (int a = 0; a < 3; ++a)
        w[a] = axial * along * axis[a] + plane * (cos_alpha * perpendicular[a] + sin_alpha * cross[a]);
    }
    if (rule == Dissipation::random_axis) {
      double along = 0.0;
      for (int a = 0; a < D; ++a) along += direction[a] * w[a];
      for (int a = 0; a < D; ++a) w[a] += (eps - 1.0) * along * direction[a];
    }
    for (int a = 0; a < D; ++a) u[a] = w[a];
  }
};

// A unit vector uniform on the circle (2D) or sphere (3D) from two uniforms in [0, 1).
template <int D>
GRANFLOW_HD inline void unit_vector(double u1, double u2, double* out) {
  constexpr double two_pi = 6.283185307179586;
  if constexpr (D == 2) {
    out[0] = std::cos(two_pi * u1);
    out[1] = std::sin(two_pi * u1);
  } else {
    const double z = 2.0 * u1 - 1.0, r = std::sqrt(1.0 - z * z);
    out[0] = r * std::cos(two_pi * u2);
    out[1] = r * std::sin(two_pi * u2);
    out[2] = z;
  }
}

}  // namespace granflow::srd
