#pragma once
// Crater observables of an impact into a granular bed (low-speed impact
// cratering, e.g. Uehara et al. 2003):
//   crater_size      bed particles displaced from their position before the
//                    impact by more than a threshold (default one bed-particle
//                    radius): the particles the impact has rearranged;
//   projectile_depth how far the projectile's lowest point has gone below the
//                    initial bed surface (negative: still above it).
// The bed is species 0, the projectile species 1.

#include <string>
#include <vector>

#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/species.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"

namespace granflow {

inline const SystemDescription observe_crater_description{"observe_crater", "crater_size (bed disks displaced beyond a threshold) and projectile_depth"};

template <int D>
using CraterObserverBase = SystemOf<Reads<Position<D>, Species, ParticleId, Radius>, Writes<>>;

template <int D>
class CraterObserver : public CraterObserverBase<D>, public Stateful {
 public:
  using View = typename CraterObserverBase<D>::View;
  // Takes every particle's position before the impact from the world as it is now.
  CraterObserver(const World& world, double threshold, double surface)
      : initial_(world.size()), threshold_(threshold), surface_(surface) {
    const View view(world);
    const auto& id = view.template read<ParticleId>();
    const auto& x = view.template read<Position<D>>();
    for (std::size_t i = 0; i < world.size(); ++i) initial_[id[i]] = x[i];
  }

  std::string name() const override { return "observe_crater"; }
  Access access() const override {
    return View::access()
        .writes_observable("crater_size", unit::none)
        .writes_observable("projectile_depth", unit::length);
  }
  StateMap save_state() const override { return {{"initial_position", flatten_vectors(initial_)}}; }
  void restore_state(const StateMap& state) override {
    unflatten_vectors(state.at("initial_position"), initial_, "crater initial positions");
  }
  void run_on(View view) override {
    const auto& x = view.template read<Position<D>>();
    const auto& species = view.template read<Species>();
    const auto& id = view.template read<ParticleId>();
    const auto& radius = view.template read<Radius>();
    std::size_t displaced = 0;
    double depth = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < view.size(); ++i) {
      if (species[i] == 0) {
        if ((x[i] - initial_[id[i]]).squaredNorm() > threshold_ * threshold_) ++displaced;
      } else {
        depth = std::max(depth, surface_ - (x[i][D - 1] - radius[i]));
      }
    }
    auto& store = view.observables();
    store.set("crater_size", static_cast<double>(displaced));
    store.set("projectile_depth", depth);
  }

 private:
  std::vector<Vec<D>> initial_;
  double threshold_;
  double surface_;
};

}  // namespace granflow
