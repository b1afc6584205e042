#pragma once
// Walls of a soft-sphere box, as functions of one sphere and one wall: a
// plane perpendicular to an axis that bounds the spheres from one side and
// may move along its normal, as rest + A sin(omega t) (`sine`) or as
// rest + A (1 - cos omega t) (`wiggle`: from rest at t = 0, between rest and
// rest + 2A, the law of LAMMPS's fix wall/gran ... wiggle), or a divider, a thin
// fixed plate perpendicular to an axis that reaches from below up to a
// height along another axis (spheres above it pass over; its top edge is a
// line they can touch).

#include <cmath>

#include "engine/core/host_device.hpp"
#include "systems/dem/contact_law.hpp"

namespace granflow::dem {

enum class WallMotion : int { sine = 0, wiggle = 1 };

struct DemWall {
  int axis = 2;
  int side = -1;  // -1: spheres above it (a floor), +1: below it; ignored by a divider
  double rest = 0.0;
  double amplitude = 0.0, omega = 0.0;
  WallMotion motion = WallMotion::sine;
  ContactLaw law;
  bool divider = false;
  int height_axis = 2;  // divider: the axis its height is measured along
  double top = 0.0;     // divider: where it ends along height_axis

  GRANFLOW_HD double position(double t) const {
    return motion == WallMotion::sine ? rest + amplitude * std::sin(omega * t)
                                      : rest + amplitude * (1.0 - std::cos(omega * t));
  }
  GRANFLOW_HD double velocity(double t) const {
    return amplitude * omega * (motion == WallMotion::sine ? std::cos(omega * t) : std::sin(omega * t));
  }
  // The middle of its motion: it stays within |amplitude| of it.
  GRANFLOW_HD double centre() const { return motion == WallMotion::sine ? rest : rest + amplitude; }
};

// A divider across `axis` at `position`, from 0 up to `top` along `height_axis`.
inline DemWall divider_wall(int axis, double position, int height_axis, double top, const ContactLaw& law) {
  DemWall w;
  w.divider = true;
  w.axis = axis;
  w.height_axis = height_axis;
  w.rest = position;
  w.top = top;
  w.law = law;
  return w;
}

// A sphere's contact with a wall: overlap, unit normal (pointing from the
// wall to the sphere: the direction of the force on it) and the rate at
// which the overlap grows.
template <int D>
struct WallContact {
  double overlap = 0.0;
  double normal[D] = {};
  double rate = 0.0;
};

// `at` and `speed`: the wall's position and velocity now (w.position(t),
// w.velocity(t), evaluated once per step for all spheres).
template <int D>
GRANFLOW_HD inline WallContact<D> wall_contact(const DemWall& w, double at, double speed, const double* x,
                                               const double* v, double radius) {
  WallContact<D> c;
  if (!w.divider) {
    const double sign = w.side < 0 ? 1.0 : -1.0;
    c.overlap = radius - sign * (x[w.axis] - at);
    c.normal[w.axis] = sign;
    c.rate = -sign * (v[w.axis] - speed);
    return c;
  }
  const double across = x[w.axis] - w.rest;
  if (x[w.height_axis] <= w.top) {
    const double sign = across >= 0.0 ? 1.0 : -1.0;
    c.overlap = radius - std::abs(across);
    c.normal[w.axis] = sign;
    c.rate = -sign * v[w.axis];
    return c;
  }
  const double up = x[w.height_axis] - w.top;
  const double distance = std::sqrt(across * across + up * up);
  c.overlap = radius - distance;
  if (distance > 0.0) {
    c.normal[w.axis] = across / distance;
    c.normal[w.height_axis] = up / distance;
  }
  c.rate = -(v[w.axis] * c.normal[w.axis] + v[w.height_axis] * c.normal[w.height_axis]);
  return c;
}

}  // namespace granflow::dem
