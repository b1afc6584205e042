#pragma once
// Crater observables of an impact into a granular bed (seed 002 problem 4):
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
#include "engine/observable_store.hpp"
#include "engine/system.hpp"
#include "engine/world.hpp"

namespace granflow {

template <int D>
class CraterObserver : public System {
 public:
  // `initial` holds every particle's position before the impact, indexed by ParticleId.
  CraterObserver(std::vector<Vec<D>> initial, double threshold, double surface)
      : initial_(std::move(initial)), threshold_(threshold), surface_(surface) {}

  std::string name() const override { return "observe_crater"; }
  Access access() const override {
    return {{Position<D>::key, Species::key, ParticleId::key, Radius::key},
            {ObservableStore::access_key("crater_size"), ObservableStore::access_key("projectile_depth")}};
  }
  void run(World& world) override {
    const auto& x = world.component<Position<D>>();
    const auto& species = world.component<Species>();
    const auto& id = world.component<ParticleId>();
    const auto& radius = world.component<Radius>();
    std::size_t displaced = 0;
    double depth = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < world.size(); ++i) {
      if (species[i] == 0) {
        if ((x[i] - initial_[id[i]]).squaredNorm() > threshold_ * threshold_) ++displaced;
      } else {
        depth = std::max(depth, surface_ - (x[i][D - 1] - radius[i]));
      }
    }
    auto& store = world.resource<ObservableStore>();
    store.set("crater_size", static_cast<double>(displaced));
    store.set("projectile_depth", depth);
  }

 private:
  std::vector<Vec<D>> initial_;
  double threshold_;
  double surface_;
};

}  // namespace granflow
