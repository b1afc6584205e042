#pragma once
// The force (and, with friction, the torque) on every soft sphere: its
// contacts with the other spheres, with the walls, and gravity. First
// gravity, then each wall with the spheres that can reach it before the
// next list build (found at each build). Then the pairs of the half
// neighbour lists, slab by slab (neighbour_list.hpp): each pair is evaluated
// once and its force given to both spheres; the slabs of one parity run in
// parallel, since none of them touches the spheres of another; each thread
// works on its own domain of slabs (thread_domains.hpp). Without
// friction the pairs of a slab are evaluated by a branch-free vectorised
// loop (pair_kernel.hpp), a block at a time. Every sum runs in an order
// fixed by the slabs and the lists (no atomics), so the result is the same
// on any thread count. The same passes book what the energy balance needs
// at this instant: the energy stored in the springs, the power the dampers
// and the sliding take and the power the moving walls give, summed per
// slab.

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "components/angular_velocity.hpp"
#include "components/clock.hpp"
#include "components/force.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/torque.hpp"
#include "components/velocity.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "systems/dem/contact_law.hpp"
#include "systems/dem/dem_walls.hpp"
#include "systems/dem/neighbour_list.hpp"
#include "systems/dem/pair_kernel.hpp"
#include "systems/dem/tangential_friction.hpp"
#include "systems/dem/thread_domains.hpp"

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
using DemContactForcesBase = SystemOf<Reads<Clock, Position<D>, Velocity<D>, AngularVelocity, Radius, Mass, Box<D>>,
                                      Writes<Force<D>, Torque, NeighbourList<D>, DemInteractions<D>>>;

template <int D>
class DemContactForces : public DemContactForcesBase<D> {
  static_assert(D == 2 || D == 3);

 public:
  using View = typename DemContactForcesBase<D>::View;
  std::string name() const override { return "dem_contact_forces"; }

  void run_on(View view) override {
    auto& in = view.template write<DemInteractions<D>>();
    if constexpr (D == 3) {
      if (in.friction.active()) return evaluate<true>(view, in);
    }
    evaluate<false>(view, in);
  }

  // Partial sums per slab of a wall's contacts: elastic, dissipated, power,
  // contacts, the force the wall is pressed with; of the slab's pairs:
  // elastic, dissipated, contacts.
  static constexpr std::size_t wall_sums = 5, pair_sums = 3;

  // For one rank of a system spread over MPI ranks (dem_domain_step.hpp),
  // whose lists are the whole system's from layer `first_layer` on: the
  // passes of one parity are the whole system's, and whether the masses and
  // radii are all alike is the whole system's answer, so that every sphere
  // sums its forces in the order, and with the kernel, of one rank.
  void as_part_of_whole(std::size_t first_layer, bool uniform_mass, bool same_radius) {
    parity_offset_ = first_layer % 2;
    uniform_mass_ = uniform_mass;
    same_radius_ = same_radius;
    mass_checked_ = true;
  }
  // The last evaluation's sums per slab: of the pairs, pair_sums each; of
  // wall w, wall_sums each.
  const std::vector<double>& pair_slab_sums() const { return pair_partial_; }
  const std::vector<std::vector<double>>& wall_slab_sums() const { return wall_partial_; }

  // The totals of `in` from the sums per slab, added in one order whatever
  // the threads or ranks that made them.
  static void add_slab_sums(const std::vector<double>& pair_partial, const std::vector<std::vector<double>>& wall_partial,
                            std::size_t slabs, DemInteractions<D>& in) {
    const std::size_t walls = wall_partial.size();
    double wall_total[wall_sums] = {}, pair_total[pair_sums] = {};
    in.wall_force.assign(walls, 0.0);
    for (std::size_t wi = 0; wi < walls; ++wi)
      for (std::size_t k = 0; k < wall_sums * slabs; k += wall_sums) {
        for (std::size_t s = 0; s < wall_sums - 1; ++s) wall_total[s] += wall_partial[wi][k + s];
        in.wall_force[wi] += wall_partial[wi][k + wall_sums - 1];
      }
    for (std::size_t k = 0; k < slabs; ++k)
      for (std::size_t s = 0; s < pair_sums; ++s) pair_total[s] += pair_partial[pair_sums * k + s];
    in.elastic = wall_total[0] + pair_total[0];
    in.dissipation_power = wall_total[1] + pair_total[1];
    in.wall_power = wall_total[2];
    in.wall_contacts = static_cast<std::uint64_t>(std::llround(wall_total[3]));
    in.contacts = static_cast<std::uint64_t>(std::llround(pair_total[2]));
  }

 private:
  static constexpr std::size_t block = 256;   // pairs evaluated together before their forces are handed out

  template <bool Friction>
  void evaluate(View view, DemInteractions<D>& in) {
    const std::size_t n = view.size();
    auto& nl = view.template write<NeighbourList<D>>();
    const std::size_t walls = in.walls.size();
    const std::size_t slabs = nl.slabs.size() - 1;
    pair_partial_.assign(pair_sums * slabs, 0.0);
    if (!mass_checked_) {
      // Masses and radii are constants of a run.
      const auto& mass = view.template read<Mass>();
      const auto& radius = view.template read<Radius>();
      uniform_mass_ = n > 0 && std::all_of(mass.values.begin(), mass.values.end(), [&](double m) { return m == mass[0]; });
      same_radius_ = n > 0 && std::all_of(radius.values.begin(), radius.values.end(), [&](double r) { return r == radius[0]; });
      mass_checked_ = true;
    }
    if (candidates_of_build_ != nl.builds || wall_candidates_.size() != walls) find_wall_candidates(view, in, nl);
    for (auto& partial : wall_partial_) partial.assign(wall_sums * slabs, 0.0);
    // Where each wall is and how fast it moves, once per step, not per slab.
    const double t = view.template read<Clock>().time;
    wall_motion_.resize(walls);
    for (std::size_t wi = 0; wi < walls; ++wi) wall_motion_[wi] = {in.walls[wi].position(t), in.walls[wi].velocity(t)};
    // Each thread its own domain of spheres and slabs (thread_domains.hpp):
    // first their weights and wall contacts, then the pairs of their slabs
    // of one parity, then of the other. Slab s gives forces to s and s + 1
    // only; along a periodic last axis the first slab also to the last, so
    // it goes alone, after the others.
    const ThreadDomains& domains = nl.domains;
    const std::size_t count = domains.count();
    std::vector<std::size_t> pieces(count);
    for (std::size_t d = 0; d < count; ++d) pieces[d] = domains.slab[d + 1] - domains.slab[d];
    for_each_piece(pieces, [&](std::size_t d, std::size_t k) {
      const std::size_t slab = domains.slab[d] + k;
      gravity(view, in, nl, nl.slabs[slab], nl.slabs[slab + 1]);
      walls_on_candidates<Friction>(view, in, nl, slab);
    });
    const std::size_t first_slab = nl.periodic_slabs ? 1 : 0;
    for (std::size_t parity = 0; parity < 2; ++parity) {
      // The slabs of this parity in each domain: from[d], from[d] + 2, ...
      std::vector<std::size_t> from(count);
      for (std::size_t d = 0; d < count; ++d) {
        const std::size_t low = std::max<std::size_t>(domains.slab[d], first_slab), high = domains.slab[d + 1];
        from[d] = low + ((low + parity_offset_) % 2 != parity ? 1 : 0);
        pieces[d] = from[d] < high ? (high - from[d] + 1) / 2 : 0;
      }
      for_each_piece(pieces, [&](std::size_t d, std::size_t k) { slab_pairs<Friction>(view, in, nl, from[d] + 2 * k); });
    }
    if (nl.periodic_slabs) slab_pairs<Friction>(view, in, nl, 0);
    add_slab_sums(pair_partial_, wall_partial_, slabs, in);
  }

  // The pairs of one slab, in order: each pair's force goes to both its spheres.
  template <bool Friction>
  void slab_pairs(View view, const DemInteractions<D>& in, NeighbourList<D>& nl, std::size_t slab) {
    const std::size_t begin = nl.offsets[nl.slabs[slab]], end = nl.offsets[nl.slabs[slab + 1]];
    double* out = &pair_partial_[pair_sums * slab];
    if constexpr (Friction) frictional_pairs(view, in, nl, begin, end, out);
    else normal_pairs(view, in, nl, begin, end, out);
  }

  // Without friction: the vectorised kernel over a block of pairs, then the
  // block's forces handed out.
  void normal_pairs(View view, const DemInteractions<D>& in, const NeighbourList<D>& nl, std::size_t begin,
                    std::size_t end, double* out) {
    auto& force = view.template write<Force<D>>();
    PairSweep<D> sweep;
    sweep.x = view.template read<Position<D>>().values.data()->data();
    sweep.v = view.template read<Velocity<D>>().values.data()->data();
    sweep.radius = view.template read<Radius>().values.data();
    sweep.mass = view.template read<Mass>().values.data();
    sweep.first = nl.first.data();
    sweep.second = nl.list.data();
    const auto& box = view.template read<Box<D>>();
    const auto half = box.half_periods();
    for (int a = 0; a < D; ++a) {
      sweep.length[a] = box.length[a];
      sweep.half[a] = half[a];
    }
    sweep.law = in.law;
    sweep.uniform_mass = uniform_mass_;
    sweep.same_radius = same_radius_;
    alignas(64) double pair_force[block * D];
    sweep.force = pair_force;
    for (std::size_t from = begin; from < end; from += block) {
      const std::size_t to = std::min(end, from + block);
      const PairTotals t = normal_pair_forces(sweep, from, to);
      out[0] += t.elastic;
      out[1] += t.dissipated;
      out[2] += t.contacts;
      // A sphere's pairs are consecutive: their forces on it are summed
      // apart and added once (a store and reload per pair would chain them).
      std::uint32_t current = nl.first[from];
      double sum[D] = {};
      for (std::size_t p = from; p < to; ++p) {
        const double* fp = &pair_force[(p - from) * D];
        if (nl.first[p] != current) {
          for (int a = 0; a < D; ++a) {
            force[current][a] += sum[a];
            sum[a] = 0.0;
          }
          current = nl.first[p];
        }
        Vec<D>& fj = force[nl.list[p]];
        for (int a = 0; a < D; ++a) {
          sum[a] += fp[a];
          fj[a] -= fp[a];
        }
      }
      for (int a = 0; a < D; ++a) force[current][a] += sum[a];
    }
  }

  // With friction (3D): each pair's normal and tangential force, and the
  // torque -r n x F_t it gives each of its spheres (with its own radius).
  void frictional_pairs(View view, const DemInteractions<D>& in, NeighbourList<D>& nl, std::size_t begin,
                        std::size_t end, double* out) {
    if constexpr (D == 3) {
      const auto& x = view.template read<Position<D>>();
      const auto& v = view.template read<Velocity<D>>();
      const auto& radius = view.template read<Radius>();
      const auto& mass = view.template read<Mass>();
      const auto& omega = view.template read<AngularVelocity>();
      auto& force = view.template write<Force<D>>();
      auto& torque = view.template write<Torque>();
      const auto& box = view.template read<Box<D>>();
      const ContactLaw law = in.law;
      const TangentialFriction friction = in.friction;
      for (std::size_t p = begin; p < end; ++p) {
        const std::uint32_t i = nl.first[p], j = nl.list[p];
        double d[D], d2 = 0.0;
        box.separation(x[i], x[j], d);
        for (int a = 0; a < D; ++a) d2 += d[a] * d[a];
        const double reach = radius[i] + radius[j];
        if (d2 >= reach * reach) {
          nl.shear[p] = Shear{};
          continue;
        }
        const double distance = std::sqrt(d2), inverse = 1.0 / distance;
        double normal[D], relative[D], rate = 0.0;
        for (int a = 0; a < D; ++a) {
          normal[a] = d[a] * inverse;
          relative[a] = v[i][a] - v[j][a];
          rate -= relative[a] * normal[a];
        }
        const double delta = reach - distance;
        const double m_eff = mass[i] * mass[j] / (mass[i] + mass[j]);
        const ContactLaw::Result r = law.normal(delta, rate, m_eff);
        // The contact points' relative velocity: v_i - v_j - (r_i w_i + r_j w_j) x n.
        const Vec<3> spin = radius[i] * omega[i] + radius[j] * omega[j];
        const double cv[3] = {relative[0] - (spin[1] * normal[2] - spin[2] * normal[1]),
                              relative[1] - (spin[2] * normal[0] - spin[0] * normal[2]),
                              relative[2] - (spin[0] * normal[1] - spin[1] * normal[0])};
        const TangentialFriction::Result tr = friction.apply(nl.shear[p], cv, normal, r.force,
                                                             law.normal_stiffness(delta), law.normal_damping(delta, m_eff));
        const Vec<3> fp(r.force * normal[0] + tr.force[0], r.force * normal[1] + tr.force[1],
                        r.force * normal[2] + tr.force[2]);
        const Vec<3> turn(-(normal[1] * tr.force[2] - normal[2] * tr.force[1]),
                          -(normal[2] * tr.force[0] - normal[0] * tr.force[2]),
                          -(normal[0] * tr.force[1] - normal[1] * tr.force[0]));
        force[i] += fp;
        force[j] -= fp;
        torque[i] += radius[i] * turn;
        torque[j] += radius[j] * turn;
        out[0] += r.elastic + tr.elastic;
        out[1] += r.dissipated + tr.dissipated;
        out[2] += 1.0;
      }
    }
  }

  // The force of each sphere of ranks [from, to) starts with its weight
  // (and its torque at zero).
  void gravity(View view, const DemInteractions<D>& in, const NeighbourList<D>& nl, std::size_t from, std::size_t to) {
    const auto& mass = view.template read<Mass>();
    double* const f = view.template write<Force<D>>().values.data()->data();
    Vec<3>* torque = view.template has<Torque>() ? view.template write<Torque>().values.data() : nullptr;
    std::array<double, D> g{};
    for (int a = 0; a < D; ++a) g[a] = in.gravity[a];
    if (nl.reorder) {
      // Ranks are indices.
      for (std::size_t i = from; i < to; ++i)
        for (int a = 0; a < D; ++a) f[i * D + static_cast<std::size_t>(a)] = mass[i] * g[a];
      if (torque)
        for (std::size_t i = from; i < to; ++i) torque[i].setZero();
      return;
    }
    for (std::size_t m = from; m < to; ++m) {
      const std::size_t i = nl.order[m];
      for (int a = 0; a < D; ++a) f[i * D + static_cast<std::size_t>(a)] = mass[i] * g[a];
      if (torque) torque[i].setZero();
    }
  }

  // The spheres that can touch each wall before the next list build: those
  // within their radius and the skin of where the wall can be at the last
  // build (between builds no sphere moves as much as half the skin). Found
  // at every build; the others' wall springs are zero (they do not touch).
  void find_wall_candidates(View view, const DemInteractions<D>& in, NeighbourList<D>& nl) {
    const auto& radius = view.template read<Radius>();
    const std::size_t walls = in.walls.size(), slabs = nl.slabs.size() - 1;
    wall_candidates_.assign(walls, {});
    wall_candidate_start_.assign(walls, std::vector<std::uint32_t>(slabs + 1, 0));
    wall_partial_.resize(walls);
    for (std::size_t wi = 0; wi < walls; ++wi) {
      const DemWall& w = in.walls[wi];
      auto& list = wall_candidates_[wi];
      auto& start = wall_candidate_start_[wi];
      // By rank, so that each slab's candidates are contiguous.
      for (std::size_t slab = 0; slab < slabs; ++slab) {
        start[slab] = static_cast<std::uint32_t>(list.size());
        for (std::size_t m = nl.slabs[slab]; m < nl.slabs[slab + 1]; ++m) {
          const std::uint32_t i = nl.order[m];
          const double reach = radius[i] + nl.skin, along = nl.reference[i][w.axis];
          bool near;
          if (w.divider) near = std::abs(along - w.rest) < reach;
          else if (w.side < 0) near = along < w.centre() + std::abs(w.amplitude) + reach;
          else near = along > w.centre() - std::abs(w.amplitude) - reach;
          if (near) list.push_back(i);
          else if (!nl.wall_shear.empty()) nl.wall_shear[i * walls + wi] = Shear{};
        }
      }
      start[slabs] = static_cast<std::uint32_t>(list.size());
    }
    candidates_of_build_ = nl.builds;
  }

  // Each wall's contacts with its candidates in one slab, one wall after
  // another (a sphere may touch two), summed per slab.
  template <bool Rotating>
  void walls_on_candidates(View view, const DemInteractions<D>& in, NeighbourList<D>& nl, std::size_t slab) {
    const auto& x = view.template read<Position<D>>();
    const auto& v = view.template read<Velocity<D>>();
    const auto& radius = view.template read<Radius>();
    const auto& mass = view.template read<Mass>();
    auto& force = view.template write<Force<D>>();
    constexpr bool rotating = D == 3 && Rotating;
    [[maybe_unused]] const Vec<3>* omega = rotating ? view.template read<AngularVelocity>().values.data() : nullptr;
    [[maybe_unused]] Vec<3>* torque = rotating ? view.template write<Torque>().values.data() : nullptr;
    const std::size_t walls = in.walls.size();
    const TangentialFriction friction = in.friction;
    for (std::size_t wi = 0; wi < walls; ++wi) {
      const DemWall& w = in.walls[wi];
      const auto [at, speed] = wall_motion_[wi];
      const auto& list = wall_candidates_[wi];
      const auto& start = wall_candidate_start_[wi];
      double* out = &wall_partial_[wi][wall_sums * slab];
      for (std::size_t c = start[slab]; c < start[slab + 1]; ++c) {
        const std::uint32_t i = list[c];
        const double mi = mass[i], ri = radius[i];
        const WallContact<D> contact = wall_contact<D>(w, at, speed, x[i].data(), v[i].data(), ri);
        if (contact.overlap <= 0.0) {
          if constexpr (rotating) nl.wall_shear[i * walls + wi] = Shear{};
          continue;
        }
        const ContactLaw::Result r = w.law.normal(contact.overlap, contact.rate, mi);
        for (int a = 0; a < D; ++a) force[i][a] += r.force * contact.normal[a];
        out[0] += r.elastic;
        out[1] += r.dissipated;
        if (!w.divider) out[2] += r.force * contact.normal[w.axis] * speed;
        out[3] += 1.0;
        out[4] += r.force;
        if constexpr (rotating) {
          // The sphere's contact point relative to the wall, which moves along its normal only.
          const Vec<3>& o = omega[i];
          const Vec<D>& vi = v[i];
          const double* nw = contact.normal;
          double cv[3] = {vi[0] - ri * (o[1] * nw[2] - o[2] * nw[1]), vi[1] - ri * (o[2] * nw[0] - o[0] * nw[2]),
                          vi[2] - ri * (o[0] * nw[1] - o[1] * nw[0])};
          if (!w.divider) cv[w.axis] -= speed;
          const TangentialFriction::Result tr =
              friction.apply(nl.wall_shear[i * walls + wi], cv, nw, r.force, w.law.normal_stiffness(contact.overlap),
                             w.law.normal_damping(contact.overlap, mi));
          for (int a = 0; a < 3; ++a) force[i][a] += tr.force[a];
          torque[i] += Vec<3>(-ri * (nw[1] * tr.force[2] - nw[2] * tr.force[1]),
                              -ri * (nw[2] * tr.force[0] - nw[0] * tr.force[2]),
                              -ri * (nw[0] * tr.force[1] - nw[1] * tr.force[0]));
          out[0] += tr.elastic;
          out[1] += tr.dissipated;
        }
      }
    }
  }

  std::vector<std::vector<std::uint32_t>> wall_candidates_;       // per wall, by rank
  std::vector<std::vector<std::uint32_t>> wall_candidate_start_;  // per wall: slab s's from [s] to [s + 1]
  std::uint64_t candidates_of_build_ = ~std::uint64_t{0};
  std::vector<std::vector<double>> wall_partial_;
  std::vector<std::pair<double, double>> wall_motion_;  // per wall: position and velocity now
  std::vector<double> pair_partial_;
  bool mass_checked_ = false, uniform_mass_ = false, same_radius_ = false;
  std::size_t parity_offset_ = 0;  // of slab 0's layer in the whole system's lists
};


}  // namespace granflow::dem
