#pragma once
// The force (and, with friction, the torque) on every soft sphere: its
// contacts with the other spheres, with the walls, and gravity. Each pair of
// the half neighbour lists is evaluated once, by its first sphere, which
// keeps the pair's force in a per-pair buffer; a second pass gives each
// sphere the pairs it is second in, through the reverse lists. Every sum
// runs in a fixed order (no atomics), so the result is the same on any
// thread count. The same pass books what the energy balance needs at this
// instant: the energy stored in the springs, the power the dampers and the
// sliding take and the power the moving walls give, summed per fixed chunk
// of spheres.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "components/angular_velocity.hpp"
#include "components/clock.hpp"
#include "components/force.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/torque.hpp"
#include "components/velocity.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/world.hpp"
#include "systems/dem/contact_law.hpp"
#include "systems/dem/dem_walls.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/dem/tangential_friction.hpp"

namespace granflow::dem {

inline const SystemDescription dem_contact_forces_description{
    "dem_contact_forces",
    "sphere-sphere and sphere-wall contact forces, friction torques and gravity (half lists, two parallel passes)"};

// What acts on the spheres, and this instant's energy terms.
template <int D>
struct DemInteractions {
  static constexpr const char* key = "dem_interactions";
  ContactLaw law;
  TangentialFriction friction;  // inactive (mu = 0) by default; spheres then carry no rotation
  std::vector<DemWall> walls;
  std::array<double, D> gravity{};

  double elastic = 0.0;           // energy in the springs (spheres and walls)
  double dissipation_power = 0.0; // taken by the dampers and the sliding
  double wall_power = 0.0;        // given by the walls' motion
  std::uint64_t contacts = 0;     // sphere-sphere pairs in contact
  std::uint64_t wall_contacts = 0;
  std::vector<double> wall_force; // per wall: the normal force the spheres press it with
};

template <int D>
class DemContactForces : public System {
  static_assert(D == 2 || D == 3);

 public:
  std::string name() const override { return "dem_contact_forces"; }
  Access access() const override {
    return Access{}
        .reads<Clock, Position<D>, Velocity<D>, AngularVelocity, Radius, Mass, DemBox<D>>()
        .template writes<Force<D>, Torque, NeighbourList<D>, DemInteractions<D>>();
  }

  void run(World& world) override {
    auto& in = world.resource<DemInteractions<D>>();
    if constexpr (D == 3) {
      if (in.friction.active()) return evaluate<true>(world, in);
    }
    evaluate<false>(world, in);
  }

 private:
  template <bool Friction>
  void evaluate(World& world, DemInteractions<D>& in) {
    const double t = world.resource<Clock>().time;
    const auto& x = world.component<Position<D>>();
    const auto& v = world.component<Velocity<D>>();
    const auto& radius = world.component<Radius>();
    const auto& mass = world.component<Mass>();
    auto& nl = world.resource<NeighbourList<D>>();
    const auto& box = world.resource<DemBox<D>>();
    auto& force = world.component<Force<D>>();
    const Vec<3>* omega = nullptr;
    Vec<3>* torque = nullptr;
    if constexpr (Friction) {
      omega = world.component<AngularVelocity>().values.data();
      torque = world.component<Torque>().values.data();
    }
    const TangentialFriction friction = in.friction;
    const std::size_t n = world.size();
    constexpr std::size_t chunk = 1024;
    const std::size_t chunks = (n + chunk - 1) / chunk;
    const std::size_t walls = in.walls.size(), width = 5 + walls;
    partial_.assign(width * chunks, 0.0);
    pair_force_.resize(nl.list.size());
    if constexpr (Friction) pair_torque_.resize(nl.list.size());
    // With one sphere mass (the usual case) every pair has the same reduced
    // mass and spring-dashpot constant: computed once, not per contact.
    if (!mass_checked_) {
      uniform_mass_ = n > 0 && std::all_of(mass.values.begin(), mass.values.end(), [&](double m) { return m == mass[0]; });
      mass_checked_ = true;
    }
    const bool uniform = uniform_mass_ && in.law.model == ContactModel::lsd;
    const double uniform_gamma = uniform ? in.law.gamma(0.5 * mass[0]) : 0.0;
    const ContactLaw law = in.law;
    std::vector<double> wall_at(walls), wall_speed(walls);
    for (std::size_t wi = 0; wi < walls; ++wi) {
      wall_at[wi] = in.walls[wi].position(t);
      wall_speed[wi] = in.walls[wi].velocity(t);
    }
    Vec<D>* pair_force = pair_force_.data();
    Vec<3>* pair_torque = pair_torque_.data();
    Shear* shear = nl.shear.data();
    Shear* wall_shear = nl.wall_shear.data();

    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
      double elastic = 0.0, dissipated = 0.0, power = 0.0, contacts = 0.0, wall_contacts = 0.0;
      double* pressing = &partial_[width * k + 5];
      const std::size_t end = std::min(n, (k + 1) * chunk);
      for (std::size_t i = k * chunk; i < end; ++i) {
        Vec<D> f;
        for (int a = 0; a < D; ++a) f[a] = mass[i] * in.gravity[a];
        Vec<3> tau = Vec<3>::Zero();
        const Vec<D> xi = x[i], vi = v[i];
        const double ri = radius[i], mi = mass[i];
        for (std::uint32_t p = nl.offsets[i]; p < nl.offsets[i + 1]; ++p) {
          const std::uint32_t j = nl.list[p];
          double d[D], d2 = 0.0;
          box.separation(xi, x[j], d);
          for (int a = 0; a < D; ++a) d2 += d[a] * d[a];
          const double reach = ri + radius[j];
          if (d2 >= reach * reach) {
            pair_force[p].setZero();
            if constexpr (Friction) {
              pair_torque[p].setZero();
              shear[p] = Shear{};
            }
            continue;
          }
          const double distance = std::sqrt(d2), inverse = 1.0 / distance;
          double normal[D], relative[D], rate = 0.0;
          for (int a = 0; a < D; ++a) {
            normal[a] = d[a] * inverse;
            relative[a] = vi[a] - v[j][a];
            rate -= relative[a] * normal[a];
          }
          const double delta = reach - distance;
          const double m_eff = uniform ? 0.5 * mi : mi * mass[j] / (mi + mass[j]);
          const double g = uniform ? uniform_gamma : law.gamma(m_eff);
          const ContactLaw::Result r = uniform ? law.lsd(delta, rate, g) : law.normal(delta, rate, m_eff);
          Vec<D> fp;
          for (int a = 0; a < D; ++a) fp[a] = r.force * normal[a];
          elastic += r.elastic;
          dissipated += r.dissipated;
          contacts += 1.0;
          if constexpr (Friction) {
            // The contact points' relative velocity: v_i - v_j - (r_i w_i + r_j w_j) x n.
            const Vec<3> spin = ri * omega[i] + radius[j] * omega[j];
            const double cv[3] = {relative[0] - (spin[1] * normal[2] - spin[2] * normal[1]),
                                  relative[1] - (spin[2] * normal[0] - spin[0] * normal[2]),
                                  relative[2] - (spin[0] * normal[1] - spin[1] * normal[0])};
            const double k_n = law.model == ContactModel::lsd ? law.stiffness : law.stiffness * std::sqrt(delta);
            const double g_n = law.model == ContactModel::lsd ? g : 1.5 * law.damping * law.stiffness * std::sqrt(delta);
            const TangentialFriction::Result tr = friction.apply(shear[p], cv, normal, r.force, k_n, g_n);
            for (int a = 0; a < 3; ++a) fp[a] += tr.force[a];
            // Both spheres feel the torque -r n x F_t (with their own radius).
            const Vec<3> turn(-(normal[1] * tr.force[2] - normal[2] * tr.force[1]),
                              -(normal[2] * tr.force[0] - normal[0] * tr.force[2]),
                              -(normal[0] * tr.force[1] - normal[1] * tr.force[0]));
            pair_torque[p] = turn;
            tau += ri * turn;
            elastic += tr.elastic;
            dissipated += tr.dissipated;
          }
          pair_force[p] = fp;
          f += fp;
        }
        for (std::size_t wi = 0; wi < walls; ++wi) {
          const DemWall& w = in.walls[wi];
          const WallContact<D> c = wall_contact<D>(w, wall_at[wi], wall_speed[wi], xi.data(), vi.data(), ri);
          if (c.overlap <= 0.0) {
            if constexpr (Friction) wall_shear[i * walls + wi] = Shear{};
            continue;
          }
          const ContactLaw::Result r = w.law.normal(c.overlap, c.rate, mi);
          for (int a = 0; a < D; ++a) f[a] += r.force * c.normal[a];
          elastic += r.elastic;
          dissipated += r.dissipated;
          if (!w.divider) power += r.force * c.normal[w.axis] * wall_speed[wi];
          pressing[wi] += r.force;
          wall_contacts += 1.0;
          if constexpr (Friction) {
            // The sphere's contact point relative to the wall, which moves along its normal only.
            const Vec<3>& o = omega[i];
            const double* nw = c.normal;
            double cv[3] = {vi[0] - ri * (o[1] * nw[2] - o[2] * nw[1]), vi[1] - ri * (o[2] * nw[0] - o[0] * nw[2]),
                            vi[2] - ri * (o[0] * nw[1] - o[1] * nw[0])};
            if (!w.divider) cv[w.axis] -= wall_speed[wi];
            const bool lsd = w.law.model == ContactModel::lsd;
            const double k_n = lsd ? w.law.stiffness : w.law.stiffness * std::sqrt(c.overlap);
            const double g_n = lsd ? w.law.gamma(mi) : 1.5 * w.law.damping * w.law.stiffness * std::sqrt(c.overlap);
            const TangentialFriction::Result tr = friction.apply(wall_shear[i * walls + wi], cv, nw, r.force, k_n, g_n);
            for (int a = 0; a < 3; ++a) f[a] += tr.force[a];
            tau += Vec<3>(-ri * (nw[1] * tr.force[2] - nw[2] * tr.force[1]), -ri * (nw[2] * tr.force[0] - nw[0] * tr.force[2]),
                          -ri * (nw[0] * tr.force[1] - nw[1] * tr.force[0]));
            elastic += tr.elastic;
            dissipated += tr.dissipated;
          }
        }
        force[i] = f;
        if constexpr (Friction) torque[i] = tau;
      }
      double* out = &partial_[width * k];
      out[0] = elastic;
      out[1] = dissipated;
      out[2] = power;
      out[3] = contacts;
      out[4] = wall_contacts;
    });
    // Each sphere's share of the pairs it is second in: the reaction.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, chunk), [&](const auto& range) {
      for (std::size_t j = range.begin(); j != range.end(); ++j) {
        Vec<D> f = force[j];
        Vec<3> tau = Vec<3>::Zero();
        for (std::uint32_t q = nl.reverse_offsets[j]; q < nl.reverse_offsets[j + 1]; ++q) {
          const std::uint32_t p = nl.reverse[q];
          f -= pair_force[p];
          if constexpr (Friction) tau += pair_torque[p];
        }
        force[j] = f;
        if constexpr (Friction) torque[j] += radius[j] * tau;
      }
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

  std::vector<double> partial_;
  std::vector<Vec<D>> pair_force_;
  std::vector<Vec<3>> pair_torque_;
  bool mass_checked_ = false, uniform_mass_ = false;
};

}  // namespace granflow::dem
