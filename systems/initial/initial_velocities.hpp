#pragma once
// Initial velocities: one speed in isotropic random directions (uniform on
// the sphere, Marsaglia 1972; a uniform polar angle would crowd the poles),
// or Maxwell-Boltzmann at a temperature. Each
// particle's draw is keyed by its id, so it is the same on any thread count.

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "components/vector.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/stream_ids.hpp"

namespace granflow {

template <int D>
Vec<D> random_direction(Philox& random) {
  if constexpr (D == 2) {
    const double angle = 2.0 * std::numbers::pi * random.uniform();
    return Vec<D>(std::cos(angle), std::sin(angle));
  } else {
    Vec<D> v;
    for (int a = 0; a < D; ++a) v[a] = random.normal();
    return v.normalized();
  }
}

template <int D>
std::vector<Vec<D>> fixed_speed_velocities(std::size_t count, double speed, std::uint64_t seed) {
  std::vector<Vec<D>> v(count);
  for (std::size_t i = 0; i < count; ++i) {
    Philox random(stream::initial_velocity, seed, 0, i);
    v[i] = speed * random_direction<D>(random);
  }
  return v;
}

template <int D>
std::vector<Vec<D>> maxwell_boltzmann_velocities(const std::vector<double>& mass, double temperature,
                                                 std::uint64_t seed) {
  std::vector<Vec<D>> v(mass.size());
  for (std::size_t i = 0; i < mass.size(); ++i) {
    Philox random(stream::initial_velocity, seed, 0, i);
    const double scale = std::sqrt(temperature / mass[i]);
    for (int a = 0; a < D; ++a) v[i][a] = scale * random.normal();
  }
  return v;
}

// Gaussian velocities of variance kT / m per component (stream `stream` of
// `seed`, one substream per particle), their mean then subtracted (the
// energy is left as it comes).
template <int D>
void draw_thermal_velocities(std::vector<Vec<D>>& velocity, double temperature, double mass, std::uint32_t stream,
                             std::uint64_t seed) {
  const auto n = static_cast<double>(velocity.size());
  Vec<D> mean = Vec<D>::Zero();
  for (std::size_t i = 0; i < velocity.size(); ++i) {
    Philox random(stream, seed, 0, i);
    for (int a = 0; a < D; ++a) velocity[i][a] = std::sqrt(temperature / mass) * random.normal();
    mean += velocity[i] / n;
  }
  for (auto& v : velocity) v -= mean;
}

// Removes the centre-of-mass velocity (a periodic gas keeps it forever), then rescales so
// the total kinetic energy is what it was before.
template <int D>
void remove_mean_velocity(std::vector<Vec<D>>& velocity, const std::vector<double>& mass) {
  Vec<D> momentum = Vec<D>::Zero();
  double total_mass = 0.0, energy_before = 0.0;
  for (std::size_t i = 0; i < velocity.size(); ++i) {
    momentum += mass[i] * velocity[i];
    total_mass += mass[i];
    energy_before += 0.5 * mass[i] * velocity[i].squaredNorm();
  }
  if (total_mass <= 0.0) return;
  const Vec<D> mean = momentum / total_mass;
  double energy_after = 0.0;
  for (std::size_t i = 0; i < velocity.size(); ++i) {
    velocity[i] -= mean;
    energy_after += 0.5 * mass[i] * velocity[i].squaredNorm();
  }
  if (energy_after > 0.0) {
    const double scale = std::sqrt(energy_before / energy_after);
    for (auto& v : velocity) v *= scale;
  }
}

}  // namespace granflow
