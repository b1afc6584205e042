#pragma once
// Particle frames (positions and velocities in particle-id order) written to
// /particles/all/{position,velocity}, with the one output.positions policy of
// every scenario: none, final (at the end), first_last (at t = 0 and at the
// end) or all (whenever the scenario's output trigger fires).

#include <spdlog/spdlog.h>

#include <memory>
#include <string>
#include <vector>

#include "components/clock.hpp"
#include "components/image_count.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/velocity.hpp"
#include "engine/core/config.hpp"
#include "engine/core/system.hpp"
#include "engine/core/system_catalogue.hpp"
#include "engine/core/view.hpp"
#include "engine/io/particle_output.hpp"
#include "engine/run/output_file.hpp"
#include "engine/run/run.hpp"

namespace granflow {

inline const SystemDescription write_particle_frames_description{"write_particle_frames", "particle positions and velocities to /particles/all, by the output.positions policy"};

template <int D>
using ParticleFrameWriterBase = SystemOf<Reads<Position<D>, Velocity<D>, ImageCount<D>, ParticleId, Clock>, Writes<OutputFile>>;

template <int D>
class ParticleFrameWriter : public ParticleFrameWriterBase<D> {
 public:
  using View = typename ParticleFrameWriterBase<D>::View;
  std::string name() const override { return "write_particle_frames"; }
  // Over ranks each sends its particles to the writing rank, by blocks of ids.
  bool observes_by_rank() const override { return true; }
  void run_on(View view) override {
    H5mdFile* file = view.template write<OutputFile>().file;
    if (!view.part().whole()) {
      const auto& clock = view.template read<Clock>();
      append_particle_frame_by_rank<D>(file, view, view.part(), clock.step, clock.time);
      return;
    }
    if (!file) return;
    const auto& clock = view.template read<Clock>();
    append_particle_frame<D>(*file, view, clock.step, clock.time);
  }
};

inline void declare_frame_keys(ConfigSchema& schema, const std::string& default_policy,
                               std::vector<std::string> policies = {"none", "final", "first_last", "all"}) {
  schema.choice("output.positions", default_policy, std::move(policies),
                "particle positions and velocities: not at all, at the end, at the start and the end, or at every "
                "output time");
}

// `outputs`: the scenario's output trigger, for the policy "all".
template <int D>
void add_particle_frames(Run& run, const TriggerPtr& outputs) {
  const std::string policy = run.config().text("output.positions");
  TriggerPtr when;
  if (policy == "final")
    when = std::make_shared<AtEnd>();
  else if (policy == "first_last")
    when = std::make_shared<AnyOf>(
        std::vector<TriggerPtr>{std::make_shared<AtTimes>(std::vector<double>{0.0}), std::make_shared<AtEnd>()});
  else if (policy == "all")
    when = outputs;
  if (!when) return;
  run.observe<ParticleFrameWriter<D>>(when);
}

}  // namespace granflow
