#pragma once
// Particle frames of an SDE ensemble (output.positions): the positions and
// velocities of its first run (the one with seed run.seed), which is what a
// trajectory viewer or an analysis of single paths needs. The runs go on in
// parallel with no result file open, so the first run keeps its frames in its
// observable history (checkpointed with it) and the reduction writes them.
//
// The particles are free: every axis has H5MD boundary "none", and the box
// written is the smallest cube, centred on the common starting point, that
// holds every frame. The frames put that starting point at the box centre
// (attribute `start` of /particles/all/position), so readers that take a box
// as [0, L) see every particle inside it; displacements are unchanged.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/config.hpp"
#include "engine/core/observable_store.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/trigger.hpp"
#include "engine/core/units.hpp"
#include "engine/core/view.hpp"
#include "engine/core/world.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/run/observable_recorder.hpp"
#include "engine/run/run.hpp"

namespace granflow::sde {

inline const SystemDescription sample_sde_frames_description{
    "sample_sde_frames", "positions and velocities of the ensemble's first run, kept for /particles/all"};

inline const std::string frame_position_series = "frame_position";
inline const std::string frame_velocity_series = "frame_velocity";

template <int D>
class SdeFrameSampler : public SystemOf<Reads<Position<D>, Velocity<D>>, Writes<>> {
 public:
  using View = typename SystemOf<Reads<Position<D>, Velocity<D>>, Writes<>>::View;
  std::string name() const override { return "sample_sde_frames"; }
  Access access() const override {
    return View::access()
        .writes_observable(frame_position_series, unit::length)
        .writes_observable(frame_velocity_series, unit::velocity);
  }
  void run_on(View view) override {
    auto& store = view.observables();
    store.set(frame_position_series, flatten(view.template read<Position<D>>()));
    store.set(frame_velocity_series, flatten(view.template read<Velocity<D>>()));
  }

 private:
  template <class Column>
  static std::vector<double> flatten(const Column& column) {
    std::vector<double> out;
    out.reserve(column.size() * D);
    for (std::size_t i = 0; i < column.size(); ++i)
      for (int a = 0; a < D; ++a) out.push_back(column[i][a]);
    return out;
  }
};

// Bytes the first run's frames take in memory, for the memory check.
inline double sde_frame_bytes(const Config& c, std::size_t outputs) {
  const std::string policy = c.text("output.positions");
  const double frames = policy == "none" ? 0.0 : policy == "final" ? 1.0 : policy == "first_last" ? 2.0
                                                                                                   : outputs + 1.0;
  return frames * 2.0 * 8.0 * static_cast<double>(c.integer("system.dimension")) *
         static_cast<double>(c.integer("system.count"));
}

// `outputs`: the run's output steps, for the policy "all" (with t = 0).
template <int D>
void add_sde_frames(Run& run, const std::vector<std::int64_t>& outputs) {
  const std::string policy = run.config().text("output.positions");
  if (policy == "none" || run.member() != 0) return;
  const auto start = std::make_shared<AtTimes>(std::vector<double>{0.0});
  TriggerPtr when;
  if (policy == "final")
    when = std::make_shared<AtEnd>();
  else if (policy == "first_last")
    when = std::make_shared<AnyOf>(std::vector<TriggerPtr>{start, std::make_shared<AtEnd>()});
  else
    when = std::make_shared<AnyOf>(std::vector<TriggerPtr>{start, std::make_shared<AtSteps>(outputs)});
  run.observe<SdeFrameSampler<D>>(when);
}

// Writes the first run's frames, its box and the particle constants.
inline void write_sde_frames(const Config& c, const ObservableHistory& first_run, H5mdFile& file) {
  const auto positions = first_run.find(frame_position_series);
  const auto velocities = first_run.find(frame_velocity_series);
  if (positions == first_run.end() || velocities == first_run.end() || positions->second.empty()) return;
  const auto dimension = static_cast<std::size_t>(c.integer("system.dimension"));
  double reach = 0.0;
  for (const auto& frame : positions->second)
    for (double x : frame.value) reach = std::max(reach, std::abs(x));
  // Two significant digits, rounded up, and never zero (a run of only t = 0).
  const double span = std::max(2.0 * reach, 1e-300);
  const double decade = std::pow(10.0, std::floor(std::log10(span)) - 1.0);
  const double edge = std::ceil(span * (1.0 + 1e-9) / decade) * decade;
  for (std::size_t k = 0; k < positions->second.size(); ++k) {
    const auto& p = positions->second[k];
    std::vector<double> centred = p.value;
    for (double& x : centred) x += 0.5 * edge;
    file.append_particle_frame("position", p.step, p.time, centred, dimension);
    const auto& v = velocities->second[k];
    file.append_particle_frame("velocity", v.step, v.time, v.value, dimension);
  }
  file.write_box(std::vector<double>(dimension, edge), std::vector<std::string>(dimension, "none"));
  file.write_attribute("/particles/all/position", "start", 0.5 * edge);
  const auto count = static_cast<std::size_t>(c.integer("system.count"));
  file.write_particle_constant("mass", std::vector<double>(count, c.real("gas.mass")), 1, unit::mass);
  std::vector<std::int32_t> id(count);
  for (std::size_t i = 0; i < count; ++i) id[i] = static_cast<std::int32_t>(i);
  file.write_particle_constant("id", id);
}

}  // namespace granflow::sde
