#pragma once
// The force (and, with friction, the torque) on every soft sphere: its
// contacts with the other spheres, with the walls, and gravity. Two
// parallel passes. The first runs over the pairs of the half neighbour
// lists, each evaluated once, and keeps each pair's force in a per-pair
// buffer; without friction this is one branch-free vectorised loop
// (pair_kernel.hpp). The second gives each sphere its gravity, the pairs it
// is first in, the reactions of those it is second in (through the reverse
// lists) and its walls. Every sum runs in a fixed order (no atomics), so
// the result is the same on any thread count. The same passes book what the
// energy balance needs at this instant: the energy stored in the springs,
// the power the dampers and the sliding take and the power the moving walls
// give, summed per fixed chunk of spheres.

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
#include "systems/dem/pair_kernel.hpp"
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
  // Chunk partial sums: pair elastic, pair dissipated, contacts, wall
  // elastic, wall dissipated, wall power, wall contacts, then the force
  // each wall is pressed with.
  static constexpr std::size_t sums = 7;

  template <bool Friction>
  void evaluate(World& world, DemInteractions<D>& in) {
    const std::size_t n = world.size();
    auto& nl = world.resource<NeighbourList<D>>();
    const std::size_t chunks = (n + chunk - 1) / chunk;
    const std::size_t walls = in.walls.size(), width = sums + walls;
    partial_.assign(width * chunks, 0.0);
    pair_force_.resize(nl.list.size());
    if (!mass_checked_) {
      const auto& mass = world.component<Mass>();
      uniform_mass_ = n > 0 && std::all_of(mass.values.begin(), mass.values.end(), [&](double m) { return m == mass[0]; });
      mass_checked_ = true;
    }
    if constexpr (Friction) frictional_pairs(world, in, nl, chunks, width);
    else normal_pairs(world, in, nl, chunks, width);
    gather(world, in, nl, chunks, width);
    double total[sums] = {};
    in.wall_force.assign(walls, 0.0);
    for (std::size_t k = 0; k < chunks; ++k) {
      for (std::size_t s = 0; s < sums; ++s) total[s] += partial_[width * k + s];
      for (std::size_t wi = 0; wi < walls; ++wi) in.wall_force[wi] += partial_[width * k + sums + wi];
    }
    in.elastic = total[0] + total[3];
    in.dissipation_power = total[1] + total[4];
    in.wall_power = total[5];
    in.contacts = static_cast<std::uint64_t>(std::llround(total[2]));
    in.wall_contacts = static_cast<std::uint64_t>(std::llround(total[6]));
  }

  // Pass 1 without friction: the vectorised kernel over each chunk's pairs.
  void normal_pairs(World& world, const DemInteractions<D>& in, const NeighbourList<D>& nl, std::size_t chunks,
                    std::size_t width) {
    const std::size_t n = world.size();
    PairSweep<D> sweep;
    sweep.x = world.component<Position<D>>().values.data()->data();
    sweep.v = world.component<Velocity<D>>().values.data()->data();
    sweep.radius = world.component<Radius>().values.data();
    sweep.mass = world.component<Mass>().values.data();
    sweep.first = nl.first.data();
    sweep.second = nl.list.data();
    const auto& box = world.resource<DemBox<D>>();
    const auto half = box.half_periods();
    for (int a = 0; a < D; ++a) {
      sweep.length[a] = box.length[a];
      sweep.half[a] = half[a];
    }
    sweep.force = pair_force_.data()->data();
    sweep.law = in.law;
    sweep.uniform_mass = uniform_mass_;
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
      const std::size_t begin = nl.offsets[k * chunk], end = nl.offsets[std::min(n, (k + 1) * chunk)];
      const PairTotals t = normal_pair_forces(sweep, begin, end);
      double* out = &partial_[width * k];
      out[0] = t.elastic;
      out[1] = t.dissipated;
      out[2] = t.contacts;
    });
  }

  // Pass 1 with friction (3D): each pair's normal and tangential force and
  // the torque turn = -n x F_t, which both spheres feel times their radius.
  void frictional_pairs(World& world, const DemInteractions<D>& in, NeighbourList<D>& nl, std::size_t chunks,
                        std::size_t width) {
    if constexpr (D == 3) {
      const auto& x = world.component<Position<D>>();
      const auto& v = world.component<Velocity<D>>();
      const auto& radius = world.component<Radius>();
      const auto& mass = world.component<Mass>();
      const auto& omega = world.component<AngularVelocity>();
      const auto& box = world.resource<DemBox<D>>();
      const std::size_t n = world.size();
      const ContactLaw law = in.law;
      const TangentialFriction friction = in.friction;
      pair_torque_.resize(nl.list.size());
      tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
        double elastic = 0.0, dissipated = 0.0, contacts = 0.0;
        const std::size_t end = std::min(n, (k + 1) * chunk);
        for (std::size_t i = k * chunk; i < end; ++i) {
          const Vec<D> xi = x[i], vi = v[i];
          const double ri = radius[i], mi = mass[i];
          for (std::uint32_t p = nl.offsets[i]; p < nl.offsets[i + 1]; ++p) {
            const std::uint32_t j = nl.list[p];
            double d[D], d2 = 0.0;
            box.separation(xi, x[j], d);
            for (int a = 0; a < D; ++a) d2 += d[a] * d[a];
            const double reach = ri + radius[j];
            if (d2 >= reach * reach) {
              pair_force_[p].setZero();
              pair_torque_[p].setZero();
              nl.shear[p] = Shear{};
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
            const double m_eff = mi * mass[j] / (mi + mass[j]);
            const ContactLaw::Result r = law.normal(delta, rate, m_eff);
            // The contact points' relative velocity: v_i - v_j - (r_i w_i + r_j w_j) x n.
            const Vec<3> spin = ri * omega[i] + radius[j] * omega[j];
            const double cv[3] = {relative[0] - (spin[1] * normal[2] - spin[2] * normal[1]),
                                  relative[1] - (spin[2] * normal[0] - spin[0] * normal[2]),
                                  relative[2] - (spin[0] * normal[1] - spin[1] * normal[0])};
            const bool lsd = law.model == ContactModel::lsd;
            const double k_n = lsd ? law.stiffness : law.stiffness * std::sqrt(delta);
            const double g_n = lsd ? law.gamma(m_eff) : 1.5 * law.damping * law.stiffness * std::sqrt(delta);
            const TangentialFriction::Result tr = friction.apply(nl.shear[p], cv, normal, r.force, k_n, g_n);
            for (int a = 0; a < 3; ++a) pair_force_[p][a] = r.force * normal[a] + tr.force[a];
            pair_torque_[p] = Vec<3>(-(normal[1] * tr.force[2] - normal[2] * tr.force[1]),
                                     -(normal[2] * tr.force[0] - normal[0] * tr.force[2]),
                                     -(normal[0] * tr.force[1] - normal[1] * tr.force[0]));
            elastic += r.elastic + tr.elastic;
            dissipated += r.dissipated + tr.dissipated;
            contacts += 1.0;
          }
        }
        double* out = &partial_[width * k];
        out[0] = elastic;
        out[1] = dissipated;
        out[2] = contacts;
      });
    }
  }

  // Pass 2, per sphere: gravity, the pairs it is first in, the reactions of
  // the pairs it is second in, and its walls.
  void gather(World& world, const DemInteractions<D>& in, NeighbourList<D>& nl, std::size_t chunks, std::size_t width) {
    const double t = world.resource<Clock>().time;
    const auto& x = world.component<Position<D>>();
    const auto& v = world.component<Velocity<D>>();
    const auto& radius = world.component<Radius>();
    const auto& mass = world.component<Mass>();
    auto& force = world.component<Force<D>>();
    const bool rotating = D == 3 && in.friction.active();
    [[maybe_unused]] const Vec<3>* omega = rotating ? world.component<AngularVelocity>().values.data() : nullptr;
    Vec<3>* torque = rotating ? world.component<Torque>().values.data() : nullptr;
    const std::size_t n = world.size(), walls = in.walls.size();
    wall_at_.resize(walls);
    wall_speed_.resize(walls);
    for (std::size_t wi = 0; wi < walls; ++wi) {
      wall_at_[wi] = in.walls[wi].position(t);
      wall_speed_[wi] = in.walls[wi].velocity(t);
    }
    const TangentialFriction friction = in.friction;
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t k) {
      double elastic = 0.0, dissipated = 0.0, power = 0.0, wall_contacts = 0.0;
      double* pressing = &partial_[width * k + sums];
      const std::size_t end = std::min(n, (k + 1) * chunk);
      for (std::size_t i = k * chunk; i < end; ++i) {
        const double mi = mass[i], ri = radius[i];
        double f[D];
        for (int a = 0; a < D; ++a) f[a] = mi * in.gravity[a];
        for (std::uint32_t p = nl.offsets[i]; p < nl.offsets[i + 1]; ++p)
          for (int a = 0; a < D; ++a) f[a] += pair_force_[p][a];
        for (std::uint32_t q = nl.reverse_offsets[i]; q < nl.reverse_offsets[i + 1]; ++q)
          for (int a = 0; a < D; ++a) f[a] -= pair_force_[nl.reverse[q]][a];
        Vec<3> tau = Vec<3>::Zero();
        if (rotating) {
          for (std::uint32_t p = nl.offsets[i]; p < nl.offsets[i + 1]; ++p) tau += pair_torque_[p];
          for (std::uint32_t q = nl.reverse_offsets[i]; q < nl.reverse_offsets[i + 1]; ++q) tau += pair_torque_[nl.reverse[q]];
          tau *= ri;
        }
        for (std::size_t wi = 0; wi < walls; ++wi) {
          const DemWall& w = in.walls[wi];
          const WallContact<D> c = wall_contact<D>(w, wall_at_[wi], wall_speed_[wi], x[i].data(), v[i].data(), ri);
          if (c.overlap <= 0.0) {
            if (rotating) nl.wall_shear[i * walls + wi] = Shear{};
            continue;
          }
          const ContactLaw::Result r = w.law.normal(c.overlap, c.rate, mi);
          for (int a = 0; a < D; ++a) f[a] += r.force * c.normal[a];
          elastic += r.elastic;
          dissipated += r.dissipated;
          if (!w.divider) power += r.force * c.normal[w.axis] * wall_speed_[wi];
          pressing[wi] += r.force;
          wall_contacts += 1.0;
          if constexpr (D == 3) {
            if (!rotating) continue;
            // The sphere's contact point relative to the wall, which moves along its normal only.
            const Vec<3>& o = omega[i];
            const Vec<D>& vi = v[i];
            const double* nw = c.normal;
            double cv[3] = {vi[0] - ri * (o[1] * nw[2] - o[2] * nw[1]), vi[1] - ri * (o[2] * nw[0] - o[0] * nw[2]),
                            vi[2] - ri * (o[0] * nw[1] - o[1] * nw[0])};
            if (!w.divider) cv[w.axis] -= wall_speed_[wi];
            const bool lsd = w.law.model == ContactModel::lsd;
            const double k_n = lsd ? w.law.stiffness : w.law.stiffness * std::sqrt(c.overlap);
            const double g_n = lsd ? w.law.gamma(mi) : 1.5 * w.law.damping * w.law.stiffness * std::sqrt(c.overlap);
            const TangentialFriction::Result tr =
                friction.apply(nl.wall_shear[i * walls + wi], cv, nw, r.force, k_n, g_n);
            for (int a = 0; a < 3; ++a) f[a] += tr.force[a];
            tau += Vec<3>(-ri * (nw[1] * tr.force[2] - nw[2] * tr.force[1]), -ri * (nw[2] * tr.force[0] - nw[0] * tr.force[2]),
                          -ri * (nw[0] * tr.force[1] - nw[1] * tr.force[0]));
            elastic += tr.elastic;
            dissipated += tr.dissipated;
          }
        }
        for (int a = 0; a < D; ++a) force[i][a] = f[a];
        if (rotating) torque[i] = tau;
      }
      double* out = &partial_[width * k];
      out[3] = elastic;
      out[4] = dissipated;
      out[5] = power;
      out[6] = wall_contacts;
    });
  }

  static constexpr std::size_t chunk = 1024;
  std::vector<double> partial_;
  std::vector<Vec<D>> pair_force_;
  std::vector<Vec<3>> pair_torque_;
  std::vector<double> wall_at_, wall_speed_;
  bool mass_checked_ = false, uniform_mass_ = false;
};

}  // namespace granflow::dem
