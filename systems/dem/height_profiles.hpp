#pragma once
// Profiles against height of soft spheres, at each output: the packing
// fraction (the volume of the spheres whose centres lie in a layer, over
// the layer's volume) and the granular temperature (m |v - <v>|^2 / D of
// the layer's spheres, about the layer's mean velocity), in layers of
// `layer` thickness from 0 to `height`. With a divider, per compartment:
// the observables end in _left and _right. DemHeightProfileAverage samples
// the same profiles more often than the outputs (so that the average runs
// over the whole shaking cycle, not the outputs' phase of it) from
// `average_from` on, and writes their time averages at the end as
// time-independent results (/results/packing_fraction_profile_mean,
// temperature_profile_mean, with the suffixes): the packing fraction as a
// plain mean, the temperature weighted by each layer's sphere count (an
// empty layer has no temperature), with the layer thickness, the number of
// samples and the time they start from as attributes of /observables
// (height_profile_layer, ..._samples, ..._average_from). Its sums are kept
// in checkpoints.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "components/clock.hpp"
#include "components/mass.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/velocity.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/observed_part.hpp"
#include "engine/core/state_map.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/run/run.hpp"

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
  double average_from = 0.0; // DemHeightProfileAverage: time from which the profiles are averaged

  std::vector<std::string> suffixes() const {
    return split_axis < 0 ? std::vector<std::string>{""} : std::vector<std::string>{"_left", "_right"};
  }
  std::size_t layers() const { return static_cast<std::size_t>(std::ceil(height / layer)); }
};

// The profiles now, per part (compartment) and layer.
struct HeightProfiles {
  std::vector<std::vector<double>> packing, temperature, count;
};

template <int D>
HeightProfiles height_profiles(const View<Reads<Position<D>, Velocity<D>, Radius, Mass>, Writes<>>& view,
                               const HeightProfileGeometry& g) {
  const auto& x = view.template read<Position<D>>();
  const auto& v = view.template read<Velocity<D>>();
  const auto& r = view.template read<Radius>();
  const auto& m = view.template read<Mass>();
  const std::size_t parts = g.suffixes().size(), k_count = g.layers();
  // Per part and layer: volume, count, mass, momentum (D), m |v|^2.
  const std::size_t w = 4 + D;
  // Over ranks each sums its own spheres, in the whole system's grouping.
  const std::vector<double> sums = view.part().sums(view.size(), parts * k_count, w, [&](std::size_t i, double* s) {
    const double h = x[i][g.up];
    if (!(h >= 0.0 && h < g.height)) return no_bin;
    const auto k = std::min(static_cast<std::size_t>(h / g.layer), k_count - 1);
    const std::size_t part = g.split_axis < 0 || x[i][g.split_axis] < g.split_at ? 0 : 1;
    s[0] = 4.0 / 3.0 * std::numbers::pi * r[i] * r[i] * r[i];
    s[1] = 1.0;
    s[2] = m[i];
    for (int a = 0; a < D; ++a) s[3 + a] = m[i] * v[i][a];
    s[3 + D] = m[i] * v[i].squaredNorm();
    return part * k_count + k;
  });
  HeightProfiles out;
  for (std::size_t part = 0; part < parts; ++part) {
    std::vector<double> packing(k_count), temperature(k_count), count(k_count);
    const double area = part == 0 ? g.area : g.area_right;
    for (std::size_t k = 0; k < k_count; ++k) {
      const double* s = &sums[(part * k_count + k) * w];
      packing[k] = s[0] / (area * g.layer);
      double mean2 = 0.0;
      for (int a = 0; a < D; ++a) mean2 += s[3 + a] * s[3 + a];
      temperature[k] = s[1] > 1 ? (s[3 + D] - mean2 / s[2]) / (D * s[1]) : 0.0;
      count[k] = s[1];
    }
    out.packing.push_back(std::move(packing));
    out.temperature.push_back(std::move(temperature));
    out.count.push_back(std::move(count));
  }
  return out;
}

template <int D>
class DemHeightProfiles : public SystemOf<Reads<Position<D>, Velocity<D>, Radius, Mass>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<Position<D>, Velocity<D>, Radius, Mass>, Writes<>>::View;
  explicit DemHeightProfiles(HeightProfileGeometry g) : g_(g) {}
  std::string name() const override { return "observe_dem_height_profiles"; }
  bool observes_by_rank() const override { return true; }
  Access access() const override {
    Access a = View::access();
    for (const std::string& suffix : g_.suffixes()) {
      a.writes_observable("packing_fraction_profile" + suffix, unit::none);
      a.writes_observable("temperature_profile" + suffix, unit::energy);
    }
    return a;
  }
  void run_on(View view) override {
    HeightProfiles now = height_profiles<D>(view, g_);
    auto& store = view.observables();
    for (std::size_t part = 0; part < now.packing.size(); ++part) {
      store.set("packing_fraction_profile" + g_.suffixes()[part], std::move(now.packing[part]));
      store.set("temperature_profile" + g_.suffixes()[part], std::move(now.temperature[part]));
    }
  }

 private:
  HeightProfileGeometry g_;
};

// When DemHeightProfileAverage samples: twenty times per shaking period, or,
// with a floor at rest (frequency 0), twenty times per output interval; at
// most once a step.
inline double profile_sample_interval(double shaking_frequency, double output_interval, double dt) {
  return std::max(dt, shaking_frequency > 0.0 ? 0.05 / shaking_frequency : 0.05 * output_interval);
}

inline const SystemDescription observe_dem_height_profile_average_description{
    "observe_dem_height_profile_average", "time averages of the height profiles, sampled through the shaking cycle"};

template <int D>
class DemHeightProfileAverage : public SystemOf<Reads<Clock, Position<D>, Velocity<D>, Radius, Mass>, Writes<>>,
                                public Stateful {
 public:
  using View = typename SystemOf<Reads<Clock, Position<D>, Velocity<D>, Radius, Mass>, Writes<>>::View;
  explicit DemHeightProfileAverage(HeightProfileGeometry g) : g_(g) {}
  std::string name() const override { return "observe_dem_height_profile_average"; }
  // Its sums are the whole system's on every rank.
  bool observes_by_rank() const override { return true; }
  void run_on(View view) override {
    if (view.template read<Clock>().time < g_.average_from) return;
    const HeightProfiles now = height_profiles<D>(view, g_);
    const std::size_t parts = now.packing.size(), k_count = g_.layers();
    // Per part and layer: sum of packing fractions, of count x temperature, of counts.
    sums_.resize(parts * k_count * 3, 0.0);
    for (std::size_t part = 0; part < parts; ++part)
      for (std::size_t k = 0; k < k_count; ++k) {
        double* a = &sums_[(part * k_count + k) * 3];
        a[0] += now.packing[part][k];
        if (now.count[part][k] > 1) {
          a[1] += now.count[part][k] * now.temperature[part][k];
          a[2] += now.count[part][k];
        }
      }
    ++samples_;
  }

  std::uint64_t samples() const { return samples_; }
  // The averaged profiles, where some sample was taken.
  void write_means(H5mdFile& file) const {
    if (samples_ == 0) return;
    const std::size_t k_count = g_.layers();
    for (std::size_t part = 0; part < g_.suffixes().size(); ++part) {
      std::vector<double> packing(k_count), temperature(k_count);
      for (std::size_t k = 0; k < k_count; ++k) {
        const double* a = &sums_[(part * k_count + k) * 3];
        packing[k] = a[0] / static_cast<double>(samples_);
        temperature[k] = a[2] > 0.0 ? a[1] / a[2] : 0.0;
      }
      file.write_result("packing_fraction_profile_mean" + g_.suffixes()[part], packing, unit::none);
      file.write_result("temperature_profile_mean" + g_.suffixes()[part], temperature, unit::energy);
    }
    file.write_attribute("/observables", "height_profile_layer", g_.layer);
    file.write_attribute("/observables", "height_profile_samples", static_cast<double>(samples_));
    file.write_attribute("/observables", "height_profile_average_from", g_.average_from);
  }

  StateMap save_state() const override {
    StateMap s;
    s["sums"] = sums_;
    s["samples"] = {static_cast<double>(samples_)};
    return s;
  }
  void restore_state(const StateMap& s) override {
    sums_ = s.at("sums");
    samples_ = static_cast<std::uint64_t>(s.at("samples").at(0));
  }

 private:
  HeightProfileGeometry g_;
  std::vector<double> sums_;
  std::uint64_t samples_ = 0;
};

// The height profiles of `geometry` at every output, and their time average
// from `geometry.average_from` on, sampled several times per shaking period
// (profile_sample_interval; kept in checkpoints as "height_profile_average")
// and written when the run ends.
template <int D>
void add_height_profiles(Run& run, const TriggerPtr& outputs, const HeightProfileGeometry& geometry, double dt) {
  const Config& c = run.config();
  run.observe<DemHeightProfiles<D>>(outputs, geometry);
  const double sample_every = profile_sample_interval(c.real("shaking.frequency"), c.real("output.interval"), dt);
  auto& average = run.keep("height_profile_average",
                           run.observe<DemHeightProfileAverage<D>>(
                               std::make_shared<EveryTime>(sample_every, c.real("run.t_stop")), geometry));
  run.at_finish([&average](H5mdFile& file, const RunOutcome&) {
    if (average.samples() == 0)
      spdlog::info("nothing sampled at or after output.average_after: no time-averaged height profiles");
    average.write_means(file);
  });
}

}  // namespace granflow::dem
