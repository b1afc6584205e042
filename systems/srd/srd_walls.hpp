#pragma once
// Walls of an SRD box and streaming between them under a constant body
// force, as functions of one particle that the CPU systems and the CUDA
// kernels share (Lamura et al. 2001; Gompper et al. 2009, sec. 3.4).
//
// A wall is a plane perpendicular to one axis. The lower wall of an axis
// bounds the fluid from below, the upper one from above; either may move
// along its normal as rest + A sin(omega t). A particle that reaches a wall
// within a step is reflected at the exact time it meets it: bounce-back
// (no-slip: the velocity relative to the wall reversed) or specular (slip:
// only the normal component reversed, relative to the wall), then streams
// on for the rest of the step. With a constant acceleration g the flight
// between reflections is exact: x + v s + g s^2 / 2.

#include <cmath>

#include "engine/core/host_device.hpp"

namespace granflow::srd {

enum class WallKind : int { no_slip = 0, slip = 1 };

struct Wall {
  int axis = 0;
  int side = -1;  // -1: lower wall (fluid on its + side), +1: upper wall
  WallKind kind = WallKind::no_slip;
  double rest = 0.0;       // position at rest (or the centre of its motion)
  double amplitude = 0.0;  // of rest + amplitude sin(omega t)
  double omega = 0.0;
  double temperature = 0.0;  // of its ghost particles
  bool ghosts = true;        // no-slip only: fill the cells it cuts with ghost particles

  GRANFLOW_HD double position(double t) const { return rest + amplitude * std::sin(omega * t); }
  GRANFLOW_HD double velocity(double t) const { return amplitude * omega * std::cos(omega * t); }
  GRANFLOW_HD bool moving() const { return amplitude != 0.0 && omega != 0.0; }
};

// A constant body force per mass (gravity, or a driving force): everywhere,
// or only on the particles in the slab from <= x[slab_axis] < to. Which
// particles feel it is decided at the start of each step; the step's flight
// of those that do is then the exact parabola.
template <int D>
struct BodyForce {
  double acceleration[D] = {};
  int slab_axis = -1;  // -1: everywhere
  double from = 0.0, to = 0.0;

  BodyForce() = default;
  // The same force in another dimension (the device step keeps the 3D one
  // for both): the common axes, 0 along the others.
  template <int E>
  GRANFLOW_HD explicit BodyForce(const BodyForce<E>& other)
      : slab_axis(other.slab_axis), from(other.from), to(other.to) {
    for (int a = 0; a < D; ++a) acceleration[a] = a < E ? other.acceleration[a] : 0.0;
  }

  GRANFLOW_HD bool any() const {
    for (int a = 0; a < D; ++a)
      if (acceleration[a] != 0.0) return true;
    return false;
  }
  GRANFLOW_HD bool acts_at(const double* x) const {
    return slab_axis < 0 || (x[slab_axis] >= from && x[slab_axis] < to);
  }
};

// How far inside the fluid a coordinate lies, seen from the wall at time t
// (negative: beyond the wall).
GRANFLOW_HD inline double depth(const Wall& wall, double coordinate, double t) {
  return wall.side < 0 ? coordinate - wall.position(t) : wall.position(t) - coordinate;
}

// The first time in (0, span] at which a particle starting at coordinate x
// with velocity v and acceleration g (along the wall's axis) at time t0
// meets the wall, or a negative number if it does not within span. A fixed
// wall: the smaller positive root of a quadratic. A moving wall: the root
// of depth(s) bracketed by 0 (inside) and the first sampled s beyond the
// wall, refined by bisection to round-off.
GRANFLOW_HD inline double wall_hit_time(const Wall& wall, double x, double v, double g, double t0, double span) {
  const auto depth_at = [&](double s) { return depth(wall, x + v * s + 0.5 * g * s * s, t0 + s); };
  if (!wall.moving()) {
    // depth(s) = d0 + b s + a s^2 with b = sigma v, a = sigma g / 2, sigma = -side.
    const double sigma = wall.side < 0 ? 1.0 : -1.0;
    const double d0 = depth_at(0.0), b = sigma * v, a = 0.5 * sigma * g;
    double roots[2];
    int count = 0;
    if (a == 0.0) {
      if (b != 0.0) roots[count++] = -d0 / b;
    } else {
      const double discriminant = b * b - 4.0 * a * d0;
      if (discriminant < 0.0) return -1.0;
      // Both roots without cancellation; q = 0 only for the double root 0.
      const double q = -0.5 * (b + (b >= 0.0 ? 1.0 : -1.0) * std::sqrt(discriminant));
      roots[count++] = q / a;
      roots[count++] = q != 0.0 ? d0 / q : 0.0;
    }
    // The earliest crossing ahead; one at s = 0 (on the wall) only if it is moving out.
    double first = -1.0;
    for (int k = 0; k < count; ++k) {
      const double r = roots[k];
      if ((r > 0.0 || (r == 0.0 && b < 0.0)) && r <= span && (first < 0.0 || r < first)) first = r;
    }
    return first;
  }
  // A moving wall: sample the step finely enough for the wall's motion,
  // then bisect the first interval that ends beyond the wall.
  constexpr int samples = 8;
  double previous = 0.0;
  for (int k = 1; k <= samples; ++k) {
    const double s = span * k / samples;
    if (depth_at(s) > 0.0) {
      previous = s;
      continue;
    }
    double inside = previous, outside = s;
    for (int iteration = 0; iteration < 60 && outside - inside > 1e-15 * span; ++iteration) {
      const double middle = 0.5 * (inside + outside);
      (depth_at(middle) > 0.0 ? inside : outside) = middle;
    }
    return outside;
  }
  return -1.0;
}

// The particle's velocity after meeting `wall` at time t (its velocity
// relative to the moving wall reversed: all of it for no-slip, its normal
// component for slip).
template <int D>
GRANFLOW_HD inline void reflect(const Wall& wall, double t, double* v) {
  const double u = wall.velocity(t);
  if (wall.kind == WallKind::no_slip) {
    for (int a = 0; a < D; ++a) v[a] = -v[a];
    v[wall.axis] += 2.0 * u;
  } else {
    v[wall.axis] = 2.0 * u - v[wall.axis];
  }
}

// The reflections one particle may have in one step. A step that needs
// more is not one SRD can take (the particle would be put back on the wall
// without its energy booked); the streaming counts such particles and the
// run stops (streaming.hpp), and the time step is refused before the run
// where a fast particle could need a quarter of them (srd_setup.hpp).
inline constexpr int most_reflections = 64;

// Streams one particle over [t0, t0 + dt] under acceleration g between the
// walls (at most `wall_count`), reflecting it at each wall it meets. Returns
// the number of reflections (most_reflections: it needed more); adds to `work` (where given) the kinetic energy
// per mass the reflections gave it, (|v'|^2 - |v|^2) / 2, which only a moving
// wall makes nonzero. Axes without walls are left for the periodic wrapping
// of the caller.
template <int D>
GRANFLOW_HD inline int stream_between_walls(double* x, double* v, const double* g, double t0, double dt,
                                            const Wall* walls, int wall_count, double* work = nullptr) {
  double done = 0.0;
  int reflections = 0;
  while (reflections < most_reflections) {
    const double left = dt - done;
    int first = -1;
    double hit = left;
    for (int w = 0; w < wall_count; ++w) {
      const int a = walls[w].axis;
      const double s = wall_hit_time(walls[w], x[a], v[a], g[a], t0 + done, left);
      if (s >= 0.0 && (first < 0 || s < hit)) {
        first = w;
        hit = s;
      }
    }
    const double s = first < 0 ? left : hit;
    for (int a = 0; a < D; ++a) {
      x[a] += v[a] * s + 0.5 * g[a] * s * s;
      v[a] += g[a] * s;
    }
    done += s;
    if (first < 0) break;
    // Exactly on the wall, not a round-off beyond it.
    x[walls[first].axis] = walls[first].position(t0 + done);
    double before = 0.0, after = 0.0;
    if (work)
      for (int a = 0; a < D; ++a) before += v[a] * v[a];
    reflect<D>(walls[first], t0 + done, v);
    if (work) {
      for (int a = 0; a < D; ++a) after += v[a] * v[a];
      *work += 0.5 * (after - before);
    }
    ++reflections;
  }
  for (int w = 0; w < wall_count; ++w)
    if (depth(walls[w], x[walls[w].axis], t0 + dt) < 0.0) x[walls[w].axis] = walls[w].position(t0 + dt);
  return reflections;
}

// The ghost particles of a cell cut by a no-slip wall (Lamura et al. 2001):
// `count` virtual particles of mass m with Maxwell-Boltzmann velocities at
// the wall's temperature about its velocity, which the cell's mean and
// temperature include but which are neither stored nor rotated. Only their
// sums matter, so they are drawn as such: their mean velocity (normal with
// variance kT / (m count) per component) and the scatter about it
// (kT / m times a chi-square of D (count - 1) degrees of freedom).
struct GhostSums {
  double mean[3] = {0.0, 0.0, 0.0};
  double scatter = 0.0;  // sum |v - mean|^2
};

template <int D, class Random>
GRANFLOW_HD inline GhostSums ghost_sums(int count, const Wall& wall, double t, double mass, Random& random) {
  GhostSums out;
  if (count <= 0) return out;
  const double spread = std::sqrt(wall.temperature / mass);
  for (int a = 0; a < D; ++a) out.mean[a] = spread / std::sqrt(static_cast<double>(count)) * random.normal();
  out.mean[wall.axis] += wall.velocity(t);
  double squares = 0.0;
  for (int k = 0; k < D * (count - 1); ++k) {
    const double z = random.normal();
    squares += z * z;
  }
  out.scatter = spread * spread * squares;
  return out;
}

}  // namespace granflow::srd
