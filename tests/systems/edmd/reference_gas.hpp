#pragma once
// The slow, obviously correct event-driven engine the fast one is tested
// against: every particle at one common time, all pairs (and all periodic
// images) checked after each event, every predicted event kept in a binary
// heap and discarded when a participant's collision count has changed
// (the classical event-driven scheme, e.g. Rapaport 2004). Same interface as edmd::EventDrivenGas.
// It keeps its own copy of positions and velocities in extended precision
// and has its own collision formulas, written directly from the textbook
// kinematics (wall and pair contact times, the pair collision), so it checks the shared collision rule too, and its round-off (it
// moves every particle at every event) stays well below the fast engine's.

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <vector>

#include "components/box.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/core/world.hpp"
#include "systems/edmd/event_driven_gas.hpp"

namespace granflow::edmd::testing {

template <int D>
class ReferenceGas {
 public:
  ReferenceGas(World& world, const CollisionParameters& parameters) : world_(world), parameters_(parameters) {
    if (!world.has_component<ParticleId>()) {
      auto& id = world.add_component<ParticleId>();
      std::iota(id.values.begin(), id.values.end(), 0u);
    }
  }

  void start(double now) {
    now_ = now;
    const std::size_t n = world_.size();
    const auto& position = world_.component<Position<D>>();
    const auto& velocity = world_.component<Velocity<D>>();
    x_.resize(n);
    v_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      x_[i] = position[i].template cast<long double>();
      v_[i] = velocity[i].template cast<long double>();
    }
    count_.assign(n, 0);
    last_collision_.assign(n, -std::numeric_limits<double>::infinity());
    queue_ = {};
    box_ = world_.resource<Box<D>>();
    for (std::uint32_t i = 0; i < n; ++i) predict(i, true);
    kinetic_energy_ = measure_kinetic_energy();
  }

  StopReason advance(double until, const AdvanceLimits& limits = {}) {
    while (true) {
      if (statistics_.pair_collisions >= limits.max_pair_collisions) return StopReason::collision_limit;
      if (kinetic_energy_ <= limits.min_kinetic_energy) return StopReason::energy_limit;
      if (queue_.size() > 16 * world_.size() * world_.size() + 1024) purge();
      while (!queue_.empty() && !valid(queue_.top())) queue_.pop();
      if (queue_.empty()) {
        move_all(until);
        return StopReason::no_events;
      }
      const Event event = queue_.top();
      if (event.time > until) {
        move_all(until);
        return StopReason::reached_time;
      }
      queue_.pop();
      move_all(event.time);
      execute(event);
    }
  }

  void synchronize(double t) { move_all(std::max(t, now_)); }
  double time() const { return now_; }
  double kinetic_energy() const { return kinetic_energy_; }
  const EventStatistics& statistics() const { return statistics_; }
  void set_event_observer(std::function<void(const EventRecord&)> observer) { observer_ = std::move(observer); }

 private:
  static constexpr std::uint32_t wall_base = std::numeric_limits<std::uint32_t>::max() - 2 * D;

  struct Event {
    double time;
    std::uint32_t i, j;  // j >= wall_base: wall on axis (j - wall_base)
    std::uint32_t count_i, count_j;
    bool operator>(const Event& other) const { return time > other.time; }
  };

  bool valid(const Event& e) const {
    return count_[e.i] == e.count_i && (e.j >= wall_base || count_[e.j] == e.count_j);
  }

  void purge() {
    std::vector<Event> keep;
    while (!queue_.empty()) {
      if (valid(queue_.top())) keep.push_back(queue_.top());
      queue_.pop();
    }
    for (const auto& e : keep) queue_.push(e);
  }

  using Real = long double;
  using Vector = Eigen::Matrix<Real, D, 1>;

  double measure_kinetic_energy() const {
    const auto& m = world_.component<Mass>();
    Real sum = 0.0;
    for (std::size_t i = 0; i < world_.size(); ++i) sum += 0.5L * m[i] * v_[i].squaredNorm();
    return static_cast<double>(sum);
  }

  // Moves everyone to time t and publishes the state to the world.
  void move_all(double t) {
    auto& position = world_.component<Position<D>>();
    auto& velocity = world_.component<Velocity<D>>();
    const Real dt = static_cast<Real>(t) - static_cast<Real>(now_);
    for (std::size_t i = 0; i < world_.size(); ++i) {
      x_[i] += v_[i] * dt;
      for (int a = 0; a < D; ++a)
        if (box_.periodic[a]) x_[i][a] -= box_.length[a] * std::floor(x_[i][a] / box_.length[a]);
      position[i] = x_[i].template cast<double>();
      velocity[i] = v_[i].template cast<double>();
    }
    now_ = t;
  }

  // Pair contact time: the smaller root of |dx + dv t| = R12.
  static Real time_to_contact(const Vector& dx, const Vector& dv, Real contact) {
    const Real b = dv.dot(dx);
    if (b >= 0) return std::numeric_limits<Real>::infinity();
    const Real d = b * b - dv.squaredNorm() * (dx.squaredNorm() - contact * contact);
    if (d <= 0) return std::numeric_limits<Real>::infinity();
    return std::max<Real>(-(b + std::sqrt(d)) / dv.squaredNorm(), 0);
  }

  // Predicts i's collisions with every other particle (only j > i when
  // `initial`, so each pair is entered once) and with the walls.
  void predict(std::uint32_t i, bool initial) {
    const auto& r = world_.component<Radius>();
    const auto& x = x_;
    const auto& v = v_;
    for (std::uint32_t j = initial ? i + 1 : 0; j < world_.size(); ++j) {
      if (j == i) continue;
      Real best = std::numeric_limits<Real>::infinity();
      // every image of j within one box length
      std::array<int, D> image;
      image.fill(-1);
      while (true) {
        Vector shift = Vector::Zero();
        bool usable = true;
        for (int a = 0; a < D; ++a) {
          if (image[a] != 0 && !box_.periodic[a]) usable = false;
          shift[a] = image[a] * box_.length[a];
        }
        if (usable) best = std::min(best, time_to_contact(x[j] + shift - x[i], v[j] - v[i], Real(r[i]) + r[j]));
        int a = 0;
        for (; a < D; ++a) {
          if (++image[a] <= 1) break;
          image[a] = -1;
        }
        if (a == D) break;
      }
      if (std::isfinite(best)) queue_.push({static_cast<double>(now_ + best), i, j, count_[i], count_[j]});
    }
    for (int a = 0; a < D; ++a) {
      if (box_.periodic[a] || v[i][a] == 0.0) continue;
      const Real target = v[i][a] > 0 ? box_.length[a] - r[i] : r[i];
      const Real dt = std::max<Real>((target - x[i][a]) / v[i][a], 0);
      queue_.push({static_cast<double>(now_ + dt), i, wall_base + static_cast<std::uint32_t>(a), count_[i], 0});
    }
  }

  void execute(const Event& e) {
    auto& x = x_;
    auto& v = v_;
    const auto& m = world_.component<Mass>();
    const auto& id = world_.component<ParticleId>();
    const std::uint32_t i = e.i;
    const bool tc_i = now_ - last_collision_[i] < parameters_.contact_time;
    if (e.j >= wall_base) {
      const int axis = static_cast<int>(e.j - wall_base);
      // inelastic wall: normal reversed, every component scaled by the restitution
      const Real restitution = tc_i ? 1.0 : parameters_.wall_restitution;
      const Real before = v[i].squaredNorm();
      v[i][axis] = -v[i][axis];
      v[i] *= restitution;
      const double lost = static_cast<double>(0.5L * m[i] * (before - v[i].squaredNorm()));
      statistics_.wall_dissipated_energy += lost;
      kinetic_energy_ -= lost;
      ++statistics_.wall_collisions;
      ++count_[i];
      last_collision_[i] = now_;
      if (observer_) observer_({now_, id[i], EventRecord::wall_partner});
      predict(i, false);
      return;
    }
    const std::uint32_t j = e.j;
    Vector dx = x[j] - x[i];
    for (int a = 0; a < D; ++a)
      if (box_.periodic[a]) dx[a] -= box_.length[a] * std::round(dx[a] / box_.length[a]);
    const bool elastic = tc_i || now_ - last_collision_[j] < parameters_.contact_time;
    const Real xi = elastic ? 1.0 : parameters_.restitution;
    // inelastic pair collision with normal restitution xi
    const Real energy_before = 0.5L * (m[i] * v[i].squaredNorm() + m[j] * v[j].squaredNorm());
    const Real b = (v[j] - v[i]).dot(dx);
    const Real r2 = dx.squaredNorm();
    const Real mi = m[i], mj = m[j];
    v[i] += ((1 + xi) * mj / (mi + mj) * b / r2) * dx;
    v[j] -= ((1 + xi) * mi / (mi + mj) * b / r2) * dx;
    const Real lost = energy_before - 0.5L * (m[i] * v[i].squaredNorm() + m[j] * v[j].squaredNorm());
    statistics_.dissipated_energy += static_cast<double>(lost);
    // r_ij . delta p_i with r_ij = x_i - x_j
    statistics_.virial += static_cast<double>(-(1 + xi) * mi * mj / (mi + mj) * b);
    kinetic_energy_ -= static_cast<double>(lost);
    ++statistics_.pair_collisions;
    ++count_[i];
    ++count_[j];
    last_collision_[i] = last_collision_[j] = now_;
    if (observer_) observer_({now_, id[i], id[j]});
    predict(i, false);
    predict(j, false);
  }

  World& world_;
  CollisionParameters parameters_;
  Box<D> box_;
  std::vector<Vector> x_;
  std::vector<Vector> v_;
  double now_ = 0.0;
  double kinetic_energy_ = 0.0;
  std::vector<std::uint32_t> count_;
  std::vector<double> last_collision_;
  std::priority_queue<Event, std::vector<Event>, std::greater<>> queue_;
  EventStatistics statistics_;
  std::function<void(const EventRecord&)> observer_;
};

}  // namespace granflow::edmd::testing
