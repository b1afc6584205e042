#pragma once
// What an SRD step can be asked to do, checked before the run. A fast
// particle (8 thermal standard deviations at the hottest temperature the run
// has, plus the shear flow, twice the fastest wall, the fall through the box
// under the force, and what the force adds over the whole run) must
//  - have a speed, a displacement per step and an energy a double holds;
//  - move at most 10^6 cells in a step (beyond, x + v dt loses the cell);
//  - between walls, cross the channel at most a quarter of the reflections a
//    step may have (srd_walls.hpp): the streaming is exact only within them.
// Lees-Edwards shear and walls of any origin do not combine; a temperature
// below 1e-150 (its fourth moments underflow) is refused.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "engine/core/config.hpp"
#include "engine/core/input_error.hpp"
#include "systems/srd/srd_walls.hpp"

namespace granflow::srd {

inline constexpr double most_cells_per_step = 1e6;

template <int D>
void check_srd_step(const Config& c, const std::array<std::int32_t, D>& cells, const std::vector<Wall>& walls,
                    const BodyForce<D>& force, double particles) {
  const double rate = c.real("shear.rate");
  if (!walls.empty() && rate > 0.0)
    throw ConfigError(fmt::format("shear.rate = {} with walls: Lees-Edwards planes and walls cannot be combined", rate));
  const double dt = c.real("srd.time_step");
  const auto steps = static_cast<double>(c.integer("run.steps"));
  double hottest = std::max(c.real("srd.temperature"), c.real("thermostat.temperature"));
  double wall_speed = 0.0;
  for (const Wall& w : walls) {
    hottest = std::max(hottest, w.temperature);
    wall_speed = std::max(wall_speed, std::abs(w.amplitude * w.omega));
  }
  double g = 0.0, longest = 0.0;
  for (int a = 0; a < D; ++a) {
    g = std::max(g, std::abs(force.acceleration[a]));
    longest = std::max(longest, static_cast<double>(cells[a]));
  }
  // Below this the fourth moments of the velocities (Sonine a2, the
  // temperature's spread) underflow: a fluid that cold is at rest in any
  // reduced units.
  constexpr double coldest = 1e-150;
  for (const char* key : {"srd.temperature", "thermostat.temperature"})
    if (c.real(key) > 0.0 && c.real(key) < coldest)
      throw ConfigError(fmt::format("{} = {:.4g} is below {:.0e}: the fluid's velocity moments underflow; choose a "
                                    "temperature nearer 1 in reduced units",
                                    key, c.real(key), coldest));
  const double fast = 8.0 * std::sqrt(hottest) + rate * (D >= 2 ? cells[1] : 0) + 2.0 * wall_speed +
                      std::sqrt(2.0 * g * longest) + (walls.empty() ? g * dt * steps : g * dt);
  const double moved = fast * dt;
  if (!std::isfinite(fast) || !(fast * fast * particles < 1e300))
    throw ConfigError(fmt::format(
        "srd.temperature = {:.4g}, thermostat.temperature = {:.4g}, shear.rate = {:.4g} and the force give speeds "
        "(about {:.4g}) whose energy over {:.3g} particles a double cannot hold",
        c.real("srd.temperature"), c.real("thermostat.temperature"), rate, fast, particles));
  if (!std::isfinite(dt * steps) || !(moved <= most_cells_per_step))
    throw ConfigError(fmt::format("srd.time_step = {:.4g} moves a fast particle (speed {:.4g}) {:.3g} cells in one "
                                  "step; at most {:.0e} (srd.time_step <= {:.3g})",
                                  dt, fast, moved, most_cells_per_step, most_cells_per_step / fast));
  for (const Wall& w : walls) {
    const double crossings = moved / cells[w.axis];
    if (crossings > most_reflections / 4.0)
      throw ConfigError(fmt::format(
          "srd.time_step = {:.4g} lets a fast particle (speed {:.4g}) cross the {} cells between the walls along {} "
          "{:.3g} times in one step; at most {} (srd.time_step <= {:.3g})",
          dt, fast, cells[w.axis], "xyz"[w.axis], crossings, most_reflections / 4,
          most_reflections / 4.0 * cells[w.axis] / fast));
  }
}

}  // namespace granflow::srd
