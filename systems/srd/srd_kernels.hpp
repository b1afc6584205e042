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

#include "engine/core/host_device.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"

namespace granflow::srd {

// Lees-Edwards state: the upper image moves with +velocity (= shear rate x
// L_y) and is displaced by +offset along axis 0 (offset in [0, L_x)).
struct Shear {
  double velocity = 0.0;
  double offset = 0.0;
};

// floor(s) as an integer, exact for |s| < 2^63, without the library call
// that std::floor is on baseline x86-64.
GRANFLOW_HD inline std::int64_t floor_index(double s) {
  const auto truncated = static_cast<std::int64_t>(s);
  return truncated - (s < static_cast<double>(truncated) ? 1 : 0);
}

// How many box lengths x lies beyond [0, length): a test for the usual case
// of at most one, a division only beyond it.
GRANFLOW_HD inline double periods_out(double x, double length) {
  if (x >= 0.0 && x < length) return 0.0;
  if (x < 0.0 && x >= -length) return -1.0;
  if (x >= length && x < 2.0 * length) return 1.0;
  return std::floor(x / length);
}

// x back into [0, length).
GRANFLOW_HD inline double wrapped(double x, double length) {
  x -= periods_out(x, length) * length;
  return x < length ? x : 0.0;  // round-off of a value just below zero
}

// x += v dt, then back into the box; crossing a shear plane k times moves the
// particle by -k offset along x and changes v_x by -k velocity (Lees-Edwards).
// CountImages: each axis' count of boxes crossed, image[a] (+1 leaving
// through the upper face), grows by this step's; a parameter of the template
// so that the usual step carries no test for it.
template <int D, bool CountImages = false>
GRANFLOW_HD inline void stream_particle(double* x, double* v, double dt, const double* length, Shear shear,
                                        std::int32_t* image = nullptr) {
  for (int a = 0; a < D; ++a) x[a] += v[a] * dt;
  if (D >= 2 && shear.velocity != 0.0) {
    const double crossings = periods_out(x[1], length[1]);
    if (crossings != 0.0) {
      x[1] -= crossings * length[1];
      x[0] -= crossings * shear.offset;
      v[0] -= crossings * shear.velocity;
      if constexpr (CountImages) image[1] += static_cast<std::int32_t>(crossings);
    }
  }
  for (int a = 0; a < D; ++a) {
    if constexpr (CountImages) image[a] += static_cast<std::int32_t>(periods_out(x[a], length[a]));
    x[a] = wrapped(x[a], length[a]);
  }
}

// Which image along y the shifted position x + shift lies in: -1 below the
// lower shear plane, +1 above the upper one, 0 inside the box.
template <int D>
GRANFLOW_HD inline int shear_image(const double* x, const double* shift, const double* length) {
  return D >= 2 ? static_cast<int>(periods_out(x[1] + shift[1], length[1])) : 0;
}

// Linear index of the cell holding x + shift. A shifted position beyond a
// shear plane belongs to the moving image: its x is taken back by the offset.
// Axes whose bit is set in `bounded` end at walls: their cells start at
// origin[a] and do not wrap (the grid reaches a layer beyond each wall).
template <int D>
GRANFLOW_HD inline std::uint32_t cell_of(const double* x, const double* shift, const double* length,
                                         const std::int32_t* cells, Shear shear, const double* origin = nullptr,
                                         unsigned bounded = 0) {
  double s[D];
  for (int a = 0; a < D; ++a) s[a] = x[a] + shift[a];
  if (D >= 2 && shear.velocity != 0.0) s[0] -= shear_image<D>(x, shift, length) * shear.offset;
  std::uint32_t index = 0;
  for (int a = D - 1; a >= 0; --a) {
    if (bounded & (1u << a)) {
      std::int64_t c = floor_index(s[a] - origin[a]);
      c = c < 0 ? 0 : (c >= cells[a] ? cells[a] - 1 : c);
      index = index * static_cast<std::uint32_t>(cells[a]) + static_cast<std::uint32_t>(c);
      continue;
    }
    std::int64_t c = floor_index(s[a]);
    if (c < 0) c += cells[a];
    if (c >= cells[a]) c -= cells[a];
    if (c < 0 || c >= cells[a]) {  // more than one box length out: only through the shear offset
      c %= cells[a];
      if (c < 0) c += cells[a];
    }
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
  return -shear_image<D>(x, shift, length) * shear.velocity;
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

  CellRotation() = default;
  // The same operator in another dimension (the device step keeps the 3D
  // one for both): its fields do not depend on the dimension, apply() does.
  template <int E>
  GRANFLOW_HD explicit CellRotation(const CellRotation<E>& other)
      : cos_alpha(other.cos_alpha), sin_alpha(other.sin_alpha), eps(other.eps), rule(other.rule) {
    for (int a = 0; a < 3; ++a) {
      axis[a] = other.axis[a];
      direction[a] = other.direction[a];
    }
  }

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

  // The operator as a D x D matrix (row-major): every rule is linear in the
  // thermal velocity, so a cell's particles need only a matrix product.
  GRANFLOW_HD void matrix(double* m) const {
    for (int b = 0; b < D; ++b) {
      double column[D];
      for (int a = 0; a < D; ++a) column[a] = a == b ? 1.0 : 0.0;
      apply(column);
      for (int a = 0; a < D; ++a) m[a * D + b] = column[a];
    }
  }
};

// One particle's collision with its cell: v -> V + M (v + image - V) - image,
// where `image` is the x velocity its cell sees it move with beyond a shear
// plane and M the cell's operator (CellRotation::matrix).
template <int D>
GRANFLOW_HD inline void collide_particle(double* v, const double* m, const double* mean, double image) {
  double u[D], w[D];
  for (int a = 0; a < D; ++a) u[a] = v[a] - mean[a];
  u[0] += image;
  for (int a = 0; a < D; ++a) {
    w[a] = 0.0;
    for (int b = 0; b < D; ++b) w[a] += m[a * D + b] * u[b];
  }
  for (int a = 0; a < D; ++a) v[a] = mean[a] + w[a];
  v[0] -= image;
}

// A unit vector uniform on the circle (2D) or sphere (3D), from a point
// uniform in the unit disk (pairs of uniforms, rejected outside it; 21 % are)
// with no trigonometric call: the disk point's angle doubled (2D), or
// Marsaglia's (1972) map to the sphere (3D). `random` gives uniforms in (0, 1).
template <int D, class Uniform>
GRANFLOW_HD inline void random_unit_vector(Uniform& random, double* out) {
  double x1, x2, s;
  do {
    x1 = 2.0 * random.uniform() - 1.0;
    x2 = 2.0 * random.uniform() - 1.0;
    s = x1 * x1 + x2 * x2;
  } while (s >= 1.0 || s == 0.0);
  if constexpr (D == 2) {
    out[0] = (x1 * x1 - x2 * x2) / s;
    out[1] = 2.0 * x1 * x2 / s;
  } else {
    const double r = 2.0 * std::sqrt(1.0 - s);
    out[0] = r * x1;
    out[1] = r * x2;
    out[2] = 1.0 - 2.0 * s;
  }
}

// The rotation of cell `c` at `step`: its random sign (2D) or axis (3D), and
// the dissipation axis, before the granular factor is set.
template <int D>
GRANFLOW_HD inline CellRotation<D> cell_rotation(const CellRotation<D>& base, std::uint64_t seed, std::uint64_t step,
                                                 std::uint64_t c) {
  CellRotation<D> r = base;
  Philox random(stream::srd_rotation, seed, step, c);
  if constexpr (D == 2) {
    if (random.uniform() >= 0.5) r.sin_alpha = -r.sin_alpha;
  } else {
    random_unit_vector<3>(random, r.axis);
  }
  if (r.rule == Dissipation::random_axis) random_unit_vector<D>(random, r.direction);
  return r;
}

}  // namespace granflow::srd
