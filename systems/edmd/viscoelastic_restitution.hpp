#pragma once
// The normal restitution of viscoelastic spheres (Brilliantov et al. 1996;
// Ramirez et al. 1999; Schwager & Poeschel 2008): Hertz contact with a
// dissipative force proportional to the rate of deformation,
//   m_eff xi'' + rho (xi^3/2 + A sqrt(xi) xi') = 0,
// which in units of the impact speed g and the maximal deformation becomes
//   x'' + x^3/2 + b sqrt(x) x' = 0,   x(0) = 0, x'(0) = 1,
// with one parameter b = (g / g_ve)^1/5, g_ve = 1 / (A^5 kappa^2) a speed of
// the material (kappa = rho / m_eff). The collision ends when the contact
// force vanishes (it cannot pull: delayed recovery), and eps(g) = -x'(end).
// Its expansion in b is 1 - C1 b + C2 b^2 - ... with
//   C1 = Gamma(3/5) sqrt(pi) / (2^1/5 5^2/5 Gamma(21/10)) = 1.15345,
//   C2 = (3/5) C1^2 = 0.79827:
// eps -> 1 at small impact speeds, so a cooling gas never collapses.
//
// The expansion runs in powers of sqrt(b) (the first odd one, b^5/2, comes
// from the delayed recovery), so eps is tabulated once against s = sqrt(b),
// in which it is smooth (RK4 per node, the end located by interpolating the
// force's zero), and read by cubic interpolation.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace granflow::edmd {

inline double viscoelastic_c1() {
  return std::tgamma(0.6) * std::sqrt(std::numbers::pi) / (std::pow(2.0, 0.2) * std::pow(5.0, 0.4) * std::tgamma(2.1));
}
inline double viscoelastic_c2() { return 0.6 * viscoelastic_c1() * viscoelastic_c1(); }

// eps of the dimensionless collision with damping b, by integrating it.
inline double viscoelastic_restitution_integrated(double b, double step = 2e-4) {
  if (b <= 0.0) return 1.0;
  const auto acceleration = [b](double x, double v) {
    const double root = std::sqrt(std::max(x, 0.0));
    return -(root * root * root + b * root * v);
  };
  const auto force = [b](double x, double v) {
    const double root = std::sqrt(std::max(x, 0.0));
    return root * (root * root + b * v);
  };
  double x = 0.0, v = 1.0;
  for (long k = 0; k < 100000000; ++k) {
    const double h = step;
    const double k1x = v, k1v = acceleration(x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = acceleration(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = acceleration(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = acceleration(x + h * k3x, v + h * k3v);
    const double nx = x + h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double nv = v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    const double f_now = force(x, v), f_next = force(nx, nv);
    if (k > 0 && (nx <= 0.0 || f_next <= 0.0)) {
      // The force's zero (or the return to x = 0) between the two steps, linearly.
      const double at = nx <= 0.0 ? x / (x - nx) : f_now / (f_now - f_next);
      return -(v + std::clamp(at, 0.0, 1.0) * (nv - v));
    }
    x = nx;
    v = nv;
  }
  return 0.0;  // not reached: the collision ends within a few units of time
}

class ViscoelasticRestitution {
 public:
  // speed: g_ve; 0 or less: no viscoelastic collisions (eps = 1).
  explicit ViscoelasticRestitution(double speed) : speed_(speed) {
    if (speed_ > 0.0) table_ = &universal_table();
  }
  bool on() const { return speed_ > 0.0; }
  double speed() const { return speed_; }

  // eps at normal impact speed g (>= 0).
  double operator()(double g) const {
    if (!on() || g <= 0.0) return 1.0;
    const double root_b = std::pow(g / speed_, 0.1);
    const double position = root_b / spacing;
    if (position >= static_cast<double>(nodes)) return viscoelastic_restitution_integrated(root_b * root_b);
    const auto k = static_cast<std::size_t>(position);
    const double t = position - static_cast<double>(k);
    // Catmull-Rom through k-1 .. k+2; below s = 0 the even terms (s^2, s^4) mirror.
    const std::vector<double>& table = *table_;
    const double p0 = k > 0 ? table[k - 1] : table[1];
    const double p1 = table[k], p2 = table[k + 1], p3 = table[k + 2];
    return p1 + 0.5 * t * (p2 - p0 + t * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + t * (3.0 * (p1 - p2) + p3 - p0)));
  }

  static constexpr std::size_t nodes = 1024;
  static constexpr double spacing = 2.0 / nodes;  // s in [0, 2] tabulated: g up to 1024 g_ve

 private:
  // eps at the nodes s = k spacing: one function for every material, built once.
  static const std::vector<double>& universal_table() {
    static const std::vector<double> table = [] {
      std::vector<double> out(nodes + 3);
      for (std::size_t k = 0; k < out.size(); ++k) {
        const double root_b = static_cast<double>(k) * spacing;
        out[k] = viscoelastic_restitution_integrated(root_b * root_b, 1e-3);
      }
      return out;
    }();
    return table;
  }

  double speed_;
  const std::vector<double>* table_ = nullptr;
};

}  // namespace granflow::edmd
