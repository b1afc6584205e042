#pragma once
// Mean kinetic energy per particle, and the granular temperature
// T = (2/d) <E_kin> (k_B = 1).

#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>
#include <tbb/blocked_range.h>

#include "components/mass.hpp"
#include "components/velocity.hpp"
#include "engine/observable_store.hpp"
#include "engine/system.hpp"
#include "engine/world.hpp"

namespace granflow {

template <int D>
double total_kinetic_energy(const World& world) {
  const auto& v = world.component<Velocity<D>>();
  const auto& m = world.component<Mass>();
  // Fixed-size chunks keep the summation order, and so the result, the same on any thread count.
  constexpr std::size_t chunk = 4096;
  const std::size_t chunks = (world.size() + chunk - 1) / chunk;
  std::vector<double> partial(chunks, 0.0);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    double sum = 0.0;
    for (std::size_t i = c * chunk; i < std::min(world.size(), (c + 1) * chunk); ++i)
      sum += 0.5 * m[i] * v[i].squaredNorm();
    partial[c] = sum;
  });
  double total = 0.0;
  for (double p : partial) total += p;
  return total;
}

template <int D>
class KineticEnergyObserver : public System {
 public:
  std::string name() const override { return "observe_kinetic_energy"; }
  Access access() const override {
    return {{Velocity<D>::key, Mass::key},
            {ObservableStore::access_key("kinetic_energy"), ObservableStore::access_key("temperature")}};
  }
  void run(World& world) override {
    const double mean = world.size() ? total_kinetic_energy<D>(world) / static_cast<double>(world.size()) : 0.0;
    auto& store = world.resource<ObservableStore>();
    store.set("kinetic_energy", mean);
    store.set("temperature", 2.0 / D * mean);
  }
};

}  // namespace granflow
