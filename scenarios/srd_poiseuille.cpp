// Poiseuille flow of the SRD fluid: a channel between two no-slip walls
// (bounce-back with ghost particles, Lamura et al. 2001), driven by a body
// force along x, kept at its temperature by the global thermostat (which
// keeps the flow: the walls fix the frame). The steady profile is the
// parabola v(y) = (g / 2 nu) y (L - y); its fitted curvature gives the
// kinematic viscosity, compared with the kinetic plus collisional viscosity
// of Kikuchi et al. 2003, and its values at the walls the slip.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "engine/run.hpp"
#include "engine/scenario.hpp"
#include "systems/srd/srd_fields.hpp"
#include "systems/srd/srd_profiles.hpp"
#include "systems/srd/srd_frames.hpp"
#include "systems/srd/srd_setup.hpp"
#include "systems/srd/srd_state_observer.hpp"
#include "systems/srd/srd_theory.hpp"
#include "systems/srd/srd_watchdog.hpp"

namespace granflow::scenarios {
namespace {

// Least-squares parabola c0 + c1 y + c2 y^2 through (k + 1/2, v_k).
std::array<double, 3> parabola(const double* v, int layers) {
  double m[3][4] = {};
  for (int k = 0; k < layers; ++k) {
    const double y = k + 0.5, p[3] = {1.0, y, y * y};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m[r][c] += p[r] * p[c];
      m[r][3] += p[r] * v[k];
    }
  }
  for (int col = 0; col < 3; ++col)  // Gauss-Jordan; the normal matrix is positive definite
    for (int r = 0; r < 3; ++r) {
      if (r == col) continue;
      const double f = m[r][col] / m[col][col];
      for (int c = col; c < 4; ++c) m[r][c] -= f * m[col][c];
    }
  return {m[0][3] / m[0][0], m[1][3] / m[1][1], m[2][3] / m[2][2]};
}

template <int D>
void build(Run& run) {
  const Config& c = run.config();
  const auto cells = srd::cells_from<D>(c);
  auto walls = srd::walls_from<D>(c, cells);
  if (walls.empty())  // the channel: no-slip walls across y at the fluid's temperature
    for (int side : {-1, +1}) {
      srd::Wall w;
      w.axis = 1;
      w.side = side;
      w.rest = side < 0 ? 0.0 : static_cast<double>(cells[1]);
      w.temperature = c.real("srd.temperature");
      walls.push_back(w);
    }
  for (const auto& w : walls)
    if (w.axis != 1 || w.kind != srd::WallKind::no_slip || w.moving())
      throw ConfigError("srd_poiseuille is a channel between resting no-slip walls across y: give walls with "
                        "axis = \"y\", kind = \"no_slip\" and no motion, or none");
  if (!c.reals("force.slab").empty())
    throw ConfigError("srd_poiseuille drives the whole channel: force.slab is for other scenarios");
  auto force = srd::force_from<D>(c, cells);
  if (c.reals("force.acceleration").empty()) force.acceleration[0] = 0.002;
  const double* acceleration = force.acceleration;
  if (acceleration[0] <= 0.0 || acceleration[1] != 0.0)
    throw ConfigError(fmt::format("srd_poiseuille drives the flow along x: force.acceleration needs x > 0 and y = 0 "
                                  "(it has x = {}, y = {})", acceleration[0], acceleration[1]));
  const auto warmup = c.integer("poiseuille.warmup_steps");
  if (warmup >= c.integer("run.steps"))
    throw ConfigError(fmt::format("poiseuille.warmup_steps = {} leaves no step to sample before run.steps = {}", warmup,
                                  c.integer("run.steps")));
  srd::add_srd_fluid<D>(run, walls, force);
  srd::add_srd_fields<D>(run, cells);
  const double alpha = c.real("srd.rotation_angle") * std::numbers::pi / 180.0;
  const auto n0 = static_cast<double>(c.integer("srd.particles_per_cell"));
  const double dt = c.real("srd.time_step");
  const double temperature = c.real("thermostat.temperature") > 0 ? c.real("thermostat.temperature") : c.real("srd.temperature");
  const double nu = srd::kinetic_viscosity(D, n0, alpha, temperature, dt) + srd::collisional_viscosity(D, n0, alpha, dt);
  run.derive("viscosity_theory", nu);
  run.derive("acceleration", acceleration[0]);
  double layer_volume = 1.0;
  for (int a = 0; a < D; ++a)
    if (a != 1) layer_volume *= cells[a];
  auto sums = std::make_shared<srd::ProfileSums>(cells[1], D);
  run.keep("profiles", *sums);
  run.observe<srd::SrdProfileSampler<D>>(std::make_shared<EverySteps>(1, warmup + 1), 1, 0, sums);
  const auto outputs = std::make_shared<EverySteps>(c.integer("output.every_steps"), warmup + c.integer("output.every_steps"));
  srd::add_srd_frames<D>(run, outputs);
  run.observe<srd::SrdProfileObserver<D>>(outputs, layer_volume, 1.0, sums);
  srd::observe_state<D>(run, std::make_shared<EverySteps>(c.integer("output.every_steps")));
  const double g = acceleration[0];
  const int layers = cells[1];
  run.at_finish([sums, g, nu, layers, layer_volume](H5mdFile& file, const RunOutcome&) {
    const auto overall = sums->overall(layer_volume, 1.0);
    const auto fit = parabola(overall.velocity.data(), layers);
    const double measured = -g / (2.0 * fit[2]);
    const double centre = fit[0] + fit[1] * 0.5 * layers + fit[2] * 0.25 * layers * layers;
    const double lower = fit[0], upper = fit[0] + fit[1] * layers + fit[2] * layers * layers;
    // Standard errors from the blocks' own fits: of the viscosity and of the
    // two wall velocities relative to the centre's.
    const auto& blocks = sums->block_velocities();
    const std::size_t count = blocks.size() / static_cast<std::size_t>(layers);
    double s[3] = {0, 0, 0}, ss[3] = {0, 0, 0};
    for (std::size_t b = 0; b < count; ++b) {
      const auto p = parabola(&blocks[b * static_cast<std::size_t>(layers)], layers);
      const double values[3] = {-g / (2.0 * p[2]), p[0] / centre, (p[0] + p[1] * layers + p[2] * layers * layers) / centre};
      for (int k = 0; k < 3; ++k) {
        s[k] += values[k];
        ss[k] += values[k] * values[k];
      }
    }
    const double nb = static_cast<double>(count);
    const auto stderr_of = [&](int k) {
      return count >= 2 ? std::sqrt(std::max(0.0, (ss[k] / nb - (s[k] / nb) * (s[k] / nb)) / (nb - 1))) : 0.0;
    };
    const double error = stderr_of(0);
    file.write_attribute("/observables", "viscosity_measured_mean", measured);
    file.write_attribute("/observables", "viscosity_measured_stderr", error);
    file.write_attribute("/observables", "viscosity_theory", nu);
    file.write_attribute("/observables", "centre_velocity", centre);
    file.write_attribute("/observables", "slip_lower", lower / centre);
    file.write_attribute("/observables", "slip_upper", upper / centre);
    file.write_attribute("/observables", "slip_lower_stderr", stderr_of(1));
    file.write_attribute("/observables", "slip_upper_stderr", stderr_of(2));
    spdlog::info("Poiseuille fit over {} samples: nu = {:.5g} +- {:.2g} (theory {:.5g}, {:+.2f} %); centre velocity {:.4g}, "
                 "wall velocities {:.3g} +- {:.2g} and {:.3g} +- {:.2g} of it",
                 sums->samples(), measured, error, nu, 100.0 * (measured / nu - 1.0), centre, lower / centre, stderr_of(1),
                 upper / centre, stderr_of(2));
  });
}

}  // namespace

GRANFLOW_REGISTER_SCENARIO(srd_poiseuille, Scenario{
  .name = "srd_poiseuille",
  .summary = "Poiseuille flow of the SRD fluid between no-slip walls: viscosity from the profile's curvature, wall slip",
  .default_output = "srd_poiseuille.h5md",
  .keys = [](ConfigSchema& s) {
    srd::SrdDefaults d;
    d.dimension = 2;
    d.cells = {40, 20};
    d.particles_per_cell = 10;
    d.angle = 130.0;
    d.dt = 0.5;
    d.temperature = 1.0;
    d.thermostat = 1.0;
    d.steps = 6000;
    srd::declare_srd_keys(s, d);
    declare_frame_keys(s, "none");
    srd::declare_srd_wall_keys(s);
    s.integer("output.every_steps", 250, 1, 1000000000, "steps between outputs (profile blocks)")
        .integer("poiseuille.warmup_steps", 1000, 0, 1000000000, "steps before the profiles are sampled");
  },
  .build = build_by_dimension<build<2>, build<3>>,
  .adopt = adopt_stored_state,
})

}  // namespace granflow::scenarios
