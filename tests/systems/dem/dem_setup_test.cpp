// The contact laws a DEM scenario's keys give (systems/dem/dem_setup.hpp):
// LAMMPS's damping rate (contact.damping_rate, vibrated_bed) against the
// restitution it implies, found by integrating an isolated head-on contact
// with the law's own force, and the walls' law beside the pairs'.

#include "systems/dem/dem_setup.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/scenario_schema.hpp"

namespace granflow::dem {
namespace {

// Restitution of an isolated normal contact of reduced mass m_eff under
// `law`: the overlap's equation of motion m_eff delta'' = -F(delta, delta')
// by fourth-order Runge-Kutta with a step of 1e-4 of the contact time, the
// contact lasting while the spheres overlap (the dashpot may pull at its
// end, as in the closed form e = exp(-eta pi / omega)).
double integrated_restitution(const ContactLaw& law, double m_eff) {
  const double speed = 1.0, dt = 1e-4 * law.contact_time(m_eff);
  const auto accel = [&](double d, double r) { return -law.normal(d, r, m_eff).force / m_eff; };
  double delta = 0.0, rate = speed;  // overlap and its growth rate
  double previous_delta = delta, previous_rate = rate;
  do {
    previous_delta = delta;
    previous_rate = rate;
    const double k1d = rate, k1r = accel(delta, rate);
    const double k2d = rate + 0.5 * dt * k1r, k2r = accel(delta + 0.5 * dt * k1d, k2d);
    const double k3d = rate + 0.5 * dt * k2r, k3r = accel(delta + 0.5 * dt * k2d, k3d);
    const double k4d = rate + dt * k3r, k4r = accel(delta + dt * k3d, k4d);
    delta += dt / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
    rate += dt / 6.0 * (k1r + 2.0 * k2r + 2.0 * k3r + k4r);
  } while (delta > 0.0);
  // The speed where the overlap crossed zero, within the last step.
  const double fraction = previous_delta / (previous_delta - delta);
  return -(previous_rate + fraction * (rate - previous_rate)) / speed;
}

TEST(DemSetup, DampingRateGivesLammpsDashpotForPairsAndWalls) {
  Config c(scenario_schema("vibrated_bed"));
  c.apply_override("contact.damping_rate=50");
  const double mass = c.real("particle.mass"), k = c.real("contact.stiffness");
  ASSERT_TRUE(damped_at_rate(c));
  EXPECT_EQ(damping_key(c), "contact.damping_rate");
  for (const double m_eff : {0.5 * mass, mass}) {  // a pair, a sphere on a wall
    const ContactLaw law = law_for_mass(c, m_eff);
    // The dashpot force is m_eff gamma_n times the normal speed.
    EXPECT_NEAR(law.gamma(m_eff), m_eff * 50.0, 1e-12 * m_eff * 50.0);
    const double eta = 0.5 * 50.0, omega = std::sqrt(k / m_eff - eta * eta);
    const double expected = std::exp(-eta * std::numbers::pi / omega);
    // At 1e4 steps per contact the interpolated crossing's error is ~1e-8 of the speed.
    EXPECT_NEAR(integrated_restitution(law, m_eff), expected, 1e-6) << m_eff;
  }
}

TEST(DemSetup, WithoutADampingRateTheRestitutionSetsTheLaw) {
  Config c(scenario_schema("vibrated_bed"));
  c.apply_override("contact.damping_rate=0");
  c.apply_override("contact.restitution=0.6");
  EXPECT_FALSE(damped_at_rate(c));
  EXPECT_EQ(damping_key(c), "contact.restitution");
  for (const double m_eff : {0.5, 1.0})
    EXPECT_NEAR(integrated_restitution(law_for_mass(c, m_eff), m_eff), 0.6, 1e-6);
  // Hertz contacts take their own damping key, whatever the rate.
  c.apply_override("contact.damping_rate=50");
  c.apply_override("contact.model=\"hertz\"");
  EXPECT_FALSE(damped_at_rate(c));
  EXPECT_EQ(damping_key(c), "contact.hertz_damping");
}

}  // namespace
}  // namespace granflow::dem
