#pragma once
// Detects inelastic collapse: a group of particles colliding infinitely often
// in finite time. Every batch of collisions, the collision rate is divided by
// the thermal speed sqrt(E/N), which makes it independent of cooling; a
// normalised rate far above the lowest seen so far, or time that no longer
// advances, means the event sequence has run away.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace granflow::edmd {

class CollapseMonitor {
 public:
  void reset(std::size_t particle_count, double now, double kinetic_energy) {
    particles_ = std::max<std::size_t>(particle_count, 1);
    batch_ = std::max<std::uint64_t>(particle_count, 1000);
    batch_start_collisions_ = 0;
    batch_start_time_ = now;
    baseline_ = std::numeric_limits<double>::infinity();
    latest_ = 0.0;
    kinetic_energy_ = kinetic_energy;
  }

  // Call after each event; true when collapse is detected.
  bool observe(std::uint64_t pair_collisions, double now, double kinetic_energy, double factor) {
    if (pair_collisions - batch_start_collisions_ < batch_) return false;
    const double elapsed = now - batch_start_time_;
    const auto collisions = static_cast<double>(pair_collisions - batch_start_collisions_);
    batch_start_collisions_ = pair_collisions;
    batch_start_time_ = now;
    kinetic_energy_ = kinetic_energy;
    elapsed_ = elapsed;
    now_ = now;
    if (elapsed <= 0.0) {
      stalled_ = true;
      return true;
    }
    const double thermal_speed = std::sqrt(std::max(kinetic_energy, 0.0) / static_cast<double>(particles_));
    if (thermal_speed <= 0.0) return false;
    latest_ = collisions / elapsed / thermal_speed;
    baseline_ = std::min(baseline_, latest_);
    return latest_ > factor * baseline_;
  }

  // The monitor's whole state, for checkpoints.
  std::vector<double> state() const {
    return {static_cast<double>(particles_), static_cast<double>(batch_), static_cast<double>(batch_start_collisions_),
            batch_start_time_, baseline_, latest_, kinetic_energy_, elapsed_, now_, stalled_ ? 1.0 : 0.0};
  }
  void restore(const std::vector<double>& s) {
    particles_ = static_cast<std::size_t>(s.at(0));
    batch_ = static_cast<std::uint64_t>(s.at(1));
    batch_start_collisions_ = static_cast<std::uint64_t>(s.at(2));
    batch_start_time_ = s.at(3);
    baseline_ = s.at(4);
    latest_ = s.at(5);
    kinetic_energy_ = s.at(6);
    elapsed_ = s.at(7);
    now_ = s.at(8);
    stalled_ = s.at(9) != 0.0;
  }

  std::string diagnosis(double contact_time) const {
    const double thermal_speed = std::sqrt(std::max(kinetic_energy_, 0.0) / static_cast<double>(particles_));
    const double expected_rate = baseline_ * thermal_speed;
    const double mean_free_time = expected_rate > 0 ? static_cast<double>(particles_) / (2.0 * expected_rate) : 0.0;
    const std::string what =
        stalled_ ? fmt::format("time stopped advancing at t = {:.9g}: {} collisions happened at one instant", now_,
                               batch_)
                 : fmt::format("at t = {:.9g} the last {} collisions took {:.3g} time units, {:.3g} times faster "
                               "than the gas collided before (rates compared at equal thermal speed)",
                               now_, batch_, elapsed_, baseline_ > 0 ? latest_ / baseline_ : 0.0);
    return fmt::format(
        "inelastic collapse: {}. Some particles collide infinitely often in finite time, so the event sequence "
        "cannot reach later times. Use the TC model: set collision.contact_time (now {:g}) to a small fraction of "
        "the mean free time, which is about {:.3g} here (e.g. collision.contact_time={:.2g}).",
        what, contact_time, mean_free_time, 1e-3 * mean_free_time);
  }

 private:
  std::size_t particles_ = 1;
  std::uint64_t batch_ = 1000;
  std::uint64_t batch_start_collisions_ = 0;
  double batch_start_time_ = 0.0;
  double baseline_ = std::numeric_limits<double>::infinity();
  double latest_ = 0.0;
  double kinetic_energy_ = 0.0;
  double elapsed_ = 0.0;
  double now_ = 0.0;
  bool stalled_ = false;
};

}  // namespace granflow::edmd
