#pragma once
// The kinematic viscosity and the wall slip of a Poiseuille flow: the
// parabola v(y) = c0 + c1 y + c2 y^2 fitted by least squares to the mean
// velocity of the layers (centres at k + 1/2, k = 0 .. layers - 1) over the
// whole sampling gives nu = -g / (2 c2) (the steady flow under the body
// force per mass g has curvature -g / nu), the centre velocity and the
// velocities at the walls y = 0 and y = layers. Their standard errors come
// from the same fit to each block of samples, the blocks taken as
// independent.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "engine/io/h5md_file.hpp"
#include "systems/observables/least_squares.hpp"
#include "systems/srd/srd_profiles.hpp"

namespace granflow::srd {

struct PoiseuilleFit {
  double viscosity = 0, viscosity_stderr = 0;
  double centre_velocity = 0;
  double slip_lower = 0, slip_upper = 0;  // wall velocity over the centre's
  double slip_lower_stderr = 0, slip_upper_stderr = 0;
};

inline std::array<double, 3> fit_layer_parabola(const double* velocity, int layers) {
  return fit_parabola(
      static_cast<std::size_t>(layers), [](std::size_t k) { return static_cast<double>(k) + 0.5; },
      [velocity](std::size_t k) { return velocity[k]; });
}

// `g`: the body force per mass along the flow; `layer_volume`: of one layer.
inline PoiseuilleFit fit_poiseuille(const ProfileSums& sums, double g, int layers, double layer_volume) {
  const auto overall = sums.overall(layer_volume, 1.0);
  const auto fit = fit_layer_parabola(overall.velocity.data(), layers);
  PoiseuilleFit out;
  out.viscosity = -g / (2.0 * fit[2]);
  out.centre_velocity = fit[0] + fit[1] * 0.5 * layers + fit[2] * 0.25 * layers * layers;
  out.slip_lower = fit[0] / out.centre_velocity;
  out.slip_upper = (fit[0] + fit[1] * layers + fit[2] * layers * layers) / out.centre_velocity;
  const auto& blocks = sums.block_velocities();
  const std::size_t count = blocks.size() / static_cast<std::size_t>(layers);
  double s[3] = {0, 0, 0}, ss[3] = {0, 0, 0};
  for (std::size_t b = 0; b < count; ++b) {
    const auto p = fit_layer_parabola(&blocks[b * static_cast<std::size_t>(layers)], layers);
    const double values[3] = {-g / (2.0 * p[2]), p[0] / out.centre_velocity,
                              (p[0] + p[1] * layers + p[2] * layers * layers) / out.centre_velocity};
    for (int k = 0; k < 3; ++k) {
      s[k] += values[k];
      ss[k] += values[k] * values[k];
    }
  }
  const double nb = static_cast<double>(count);
  const auto stderr_of = [&](int k) {
    return count >= 2 ? std::sqrt(std::max(0.0, (ss[k] / nb - (s[k] / nb) * (s[k] / nb)) / (nb - 1))) : 0.0;
  };
  out.viscosity_stderr = stderr_of(0);
  out.slip_lower_stderr = stderr_of(1);
  out.slip_upper_stderr = stderr_of(2);
  return out;
}

// The fit as attributes of /observables, beside the theory's `nu`.
inline void write_poiseuille_fit(H5mdFile& file, const PoiseuilleFit& f, double nu, std::int64_t samples) {
  file.write_attribute("/observables", "viscosity_measured_mean", f.viscosity);
  file.write_attribute("/observables", "viscosity_measured_stderr", f.viscosity_stderr);
  file.write_attribute("/observables", "viscosity_theory", nu);
  file.write_attribute("/observables", "centre_velocity", f.centre_velocity);
  file.write_attribute("/observables", "slip_lower", f.slip_lower);
  file.write_attribute("/observables", "slip_upper", f.slip_upper);
  file.write_attribute("/observables", "slip_lower_stderr", f.slip_lower_stderr);
  file.write_attribute("/observables", "slip_upper_stderr", f.slip_upper_stderr);
  spdlog::info("Poiseuille fit over {} samples: nu = {:.5g} +- {:.2g} (theory {:.5g}, {:+.2f} %); centre velocity {:.4g}, "
               "wall velocities {:.3g} +- {:.2g} and {:.3g} +- {:.2g} of it",
               samples, f.viscosity, f.viscosity_stderr, nu, 100.0 * (f.viscosity / nu - 1.0), f.centre_velocity,
               f.slip_lower, f.slip_lower_stderr, f.slip_upper, f.slip_upper_stderr);
}

}  // namespace granflow::srd
