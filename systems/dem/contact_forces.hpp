#pragma once
// The force on every soft sphere: its contacts with the spheres of its
// neighbour list (full lists, so each sphere sums its own force: no atomics,
// the same sums on any thread count), with the walls, and gravity. The
// same pass books what the energy balance needs at this instant: the
// elastic energy stored in the contacts, the power the dampers take and the
// power the moving walls give, summed per fixed chunk of spheres (each pair
// is seen from both sides and counted half from each).

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "components/clock.hpp"
#include "components/force.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"
#include "systems/dem/contact_law.hpp"
#include "systems/dem/dem_walls.hpp"
#include "systems/dem/neighbour_list.hpp"

namespace granflow::dem {

inline const SystemDescription dem_contact_forces_description{
    "dem_contact_forces", "sphere-sphere and sphere-wall contact forces and gravity (full neighbour lists, parallel_for)"};

// What acts on the spheres, and this instant's energy terms.
template <int D>
struct DemInteractions {
  static constexpr const char* key = "dem_interactions";
  ContactLaw law;
  std::vector<DemWall> walls;
  std::array<double, D> gravity{};

  double elastic = 0.0;           // energy in the springs (spheres and walls)
  double dissipation_power = 0.0; // taken by the dampers
  double wall_power = 0.0;        // given by the walls' motion
  std::uint64_t contacts = 0;     // sphere-sphere pairs in contact
  std::uint64_t wall_contacts = 0;
  std::vector<double> wall_force; // per wall: the normal force the spheres press it with
};

template <int D>
class DemContactForces : public System {
 public:
  std::string name() const override { return "dem_contact_forces"; }
  Access access() const override {
    return Access{}
        .reads<Clock, Position<D>, Velocity<D>, Radius, Mass, NeighbourList<D>, DemBox<D>>()
        .template writes<Force<D>, DemInteractions<D>>();
  }

  void run(World& world) override {
    const double t = world.resource<Clock>().time;
    const auto& x = world.component<Position<D>>();
    const auto& v = world.component<Velocity<D>>();
    const auto& radius = world.component<Radius>();
    const auto& mass = world.component<Mass>();
    const auto& nl = world.resource<NeighbourList<D>>();
    const auto& box = world.resource<DemBox<D>>();
    auto& in = world.resource<DemInteractions<D>>();
    auto& force = world.component<Force<D>>();
    const std::size_t n = world.size();
    constexpr std::size_t chunk = 1024;
    const std::size_t chunks = (n + chunk - 1) / chunk;
    const std::size_t walls = in.walls.size(), width = 5 + walls;
    partial_.assign(width * chunks, 0.0);
    // With one sphere mass (the usual case) every pair has the same reduced
    // mass and spring-dashpot constant: computed once, not per contact.
    if (!mass_checked_) {
      uniform_mass_ = n > 0 && std::all_of(mass.values.begin(), mass.values.end(), [&](double m) { return m == mass[0]; });
      mass_checked_ = true;
    }
    const bool uniform = uniform_mass_ && in.law.model == ContactModel::lsd;
    const double uniform_gamma = uniform ? in.law.gamma(0.5 * mass[0]) : 0.0;
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
      double elastic = 0.0, dissipated = 0.0, power = 0.0, contacts = 0.0, wall_contacts = 0.0;
      double* pressing = &partial_[width * k + 5];
      const std::size_t end = std::min(n, (k + 1) * chunk);
      for (std::size_t i = k * chunk; i < end; ++i) {
        Vec<D> f;
        for (int a = 0; a < D; ++a) f[a] = mass[i] * in.gravity[a];
        for (std::uint32_t q = nl.offsets[i]; q < nl.offsets[i + 1]; ++q) {
          const std::uint32_t j = nl.list[q];
          double d[D], d2 = 0.0;
          box.separation(x[i], x[j], d);
          for (int a = 0; a < D; ++a) d2 += d[a] * d[a];
          const double reach = radius[i] + radius[j];
          if (d2 >= reach * reach) continue;
          const double distance = std::sqrt(d2), inverse = 1.0 / distance;
          double normal[D], rate = 0.0;
          for (int a = 0; a < D; ++a) {
            normal[a] = d[a] * inverse;
            rate -= (v[i][a] - v[j][a]) * normal[a];
          }
          const ContactLaw::Result r =
              uniform ? in.law.lsd(reach - distance, rate, uniform_gamma)
                      : in.law.normal(reach - distance, rate, mass[i] * mass[j] / (mass[i] + mass[j]));
          for (int a = 0; a < D; ++a) f[a] += r.force * normal[a];
          elastic += 0.5 * r.elastic;
          dissipated += 0.5 * r.dissipated;
          contacts += 0.5;
        }
        for (std::size_t wi = 0; wi < walls; ++wi) {
          const DemWall& w = in.walls[wi];
          const WallContact<D> c = wall_contact<D>(w, x[i].data(), v[i].data(), radius[i], t);
          if (c.overlap <= 0.0) continue;
          const ContactLaw::Result r = w.law.normal(c.overlap, c.rate, mass[i]);
          for (int a = 0; a < D; ++a) f[a] += r.force * c.normal[a];
          elastic += r.elastic;
          dissipated += r.dissipated;
          if (!w.divider) power += r.force * c.normal[w.axis] * w.velocity(t);
          pressing[wi] += r.force;
          wall_contacts += 1.0;
        }
        force[i] = f;
      }
      double* out = &partial_[width * k];
      out[0] = elastic;
      out[1] = dissipated;
      out[2] = power;
      out[3] = contacts;
      out[4] = wall_contacts;
    });
    double sums[5] = {0, 0, 0, 0, 0};
    in.wall_force.assign(walls, 0.0);
    for (std::size_t k = 0; k < chunks; ++k) {
      for (int s = 0; s < 5; ++s) sums[s] += partial_[width * k + static_cast<std::size_t>(s)];
      for (std::size_t wi = 0; wi < walls; ++wi) in.wall_force[wi] += partial_[width * k + 5 + wi];
    }
    in.elastic = sums[0];
    in.dissipation_power = sums[1];
    in.wall_power = sums[2];
    in.contacts = static_cast<std::uint64_t>(std::llround(sums[3]));
    in.wall_contacts = static_cast<std::uint64_t>(std::llround(sums[4]));
  }

 private:
  std::vector<double> partial_;
  bool mass_checked_ = false, uniform_mass_ = false;
};

}  // namespace granflow::dem
