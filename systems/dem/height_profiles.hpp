#pragma once
// Profiles against height of soft spheres, at each output: the packing
// fraction (the volume of the spheres whose centres lie in a layer, over
// the layer's volume) and the granular temperature (m |v - <v>|^2 / D of
// the layer's spheres, about the layer's mean velocity), in layers of
// `layer` thickness from 0 to `height`. With a divider, per compartment:
// the observables end in _left and _right.

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/observable_store.hpp"
#include "engine/system.hpp"
#include "engine/system_catalogue.hpp"
#include "engine/units.hpp"
#include "engine/world.hpp"

namespace granflow::dem {

inline const SystemDescription observe_dem_height_profiles_description{
    "observe_dem_height_profiles", "packing fraction and granular temperature against height (per compartment)"};

struct HeightProfileGeometry {
  int up = 2;                // the height axis
  double height = 1.0;       // profiles from 0 to here
  double layer = 1.0;        // layer thickness
  double area = 1.0;         // of a layer (of one compartment, with a divider)
  int split_axis = -1;       // -1: one profile; else the divider's axis
  double split_at = 0.0;     // and its position
  double area_right = 1.0;   // of a layer of the right compartment
};

template <int D>
class DemHeightProfiles : public System {
 public:
  explicit DemHeightProfiles(HeightProfileGeometry g) : g_(g) {}
  std::string name() const override { return "observe_dem_height_profiles"; }
  Access access() const override {
    Access a;
    a.reads<Position<D>, Velocity<D>, Radius, Mass>();
    for (const std::string& suffix : suffixes()) {
      a.writes_observable("packing_fraction_profile" + suffix, unit::none);
      a.writes_observable("temperature_profile" + suffix, unit::energy);
    }
    return a;
  }
  std::vector<std::string> suffixes() const {
    return g_.split_axis < 0 ? std::vector<std::string>{""} : std::vector<std::string>{"_left", "_right"};
  }
  std::size_t layers() const { return static_cast<std::size_t>(std::ceil(g_.height / g_.layer)); }

  void run(World& world) override {
    const auto& x = world.component<Position<D>>();
    const auto& v = world.component<Velocity<D>>();
    const auto& r = world.component<Radius>();
    const auto& m = world.component<Mass>();
    const std::size_t parts = suffixes().size(), k_count = layers();
    // Per part and layer: volume, count, mass, momentum (D), m |v|^2.
    const std::size_t w = 4 + D;
    std::vector<double> sums(parts * k_count * w, 0.0);
    for (std::size_t i = 0; i < world.size(); ++i) {
      const double h = x[i][g_.up];
      if (h < 0.0 || h >= g_.height) continue;
      const auto k = static_cast<std::size_t>(h / g_.layer);
      const std::size_t part = g_.split_axis < 0 || x[i][g_.split_axis] < g_.split_at ? 0 : 1;
      double* s = &sums[(part * k_count + k) * w];
      s[0] += 4.0 / 3.0 * std::numbers::pi * r[i] * r[i] * r[i];
      s[1] += 1.0;
      s[2] += m[i];
      for (int a = 0; a < D; ++a) s[3 + a] += m[i] * v[i][a];
      s[3 + D] += m[i] * v[i].squaredNorm();
    }
    auto& store = world.resource<ObservableStore>();
    for (std::size_t part = 0; part < parts; ++part) {
      std::vector<double> packing(k_count), temperature(k_count);
      const double area = part == 0 ? g_.area : g_.area_right;
      for (std::size_t k = 0; k < k_count; ++k) {
        const double* s = &sums[(part * k_count + k) * w];
        packing[k] = s[0] / (area * g_.layer);
        double mean2 = 0.0;
        for (int a = 0; a < D; ++a) mean2 += s[3 + a] * s[3 + a];
        temperature[k] = s[1] > 1 ? (s[3 + D] - mean2 / s[2]) / (D * s[1]) : 0.0;
      }
      store.set("packing_fraction_profile" + suffixes()[part], std::move(packing));
      store.set("temperature_profile" + suffixes()[part], std::move(temperature));
    }
  }

 private:
  HeightProfileGeometry g_;
};

}  // namespace granflow::dem
