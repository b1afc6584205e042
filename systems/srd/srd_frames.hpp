#pragma once
// Particle frames of an SRD fluid (output.positions): the particles have
// ids in the order of the initial state (add_srd_fluid), so that every frame lists
// them in that order however the binning sorts them in memory, and they
// count their periodic images (the streaming adds each step's), so that
// frames unwrap. The masses and ids are written at the end; the particles
// are points (no radius). The device step does not follow particles by id:
// frames there are refused.

#include <fmt/format.h>

#include <numeric>
#include <vector>

#include "components/image_count.hpp"
#include "components/particle_id.hpp"
#include "engine/core/config.hpp"
#include "engine/core/units.hpp"
#include "engine/io/h5md_file.hpp"
#include "engine/run/run.hpp"
#include "systems/observables/particle_frames.hpp"
#include "systems/srd/srd_cells.hpp"

namespace granflow::srd {

template <int D>
void add_srd_frames(Run& run, const TriggerPtr& outputs) {
  const Config& c = run.config();
  if (c.text("output.positions") == "none") return;
  if (c.text("srd.device") != "cpu")
    throw ConfigError(fmt::format("output.positions = \"{}\" needs srd.device = \"cpu\": the device step does not "
                                  "follow the particles by id",
                                  c.text("output.positions")));
  World& world = run.world();
  // The ids come with the initial state (add_srd_fluid); a resumed run has
  // them and the images from its checkpoint.
  if (!world.has_component<ParticleId>()) throw std::logic_error("SRD frames without particle ids");
  if (!world.has_component<ImageCount<D>>())
    for (auto& image : world.add_component<ImageCount<D>>().values) image.setZero();
  add_particle_frames<D>(run, outputs);
  // As many as the frames hold: over ranks no process holds them all.
  const double mass = world.resource<SrdCells<D>>().particle_mass;
  run.at_finish([mass](H5mdFile& file, const RunOutcome&) {
    const std::size_t count = file.particles_in_frames("position");
    if (count == 0) return;
    file.write_particle_constant("mass", std::vector<double>(count, mass), 1, unit::mass);
    std::vector<std::int32_t> id(count);
    std::iota(id.begin(), id.end(), 0);
    file.write_particle_constant("id", id);
  });
}

// Compiled once for both dimensions, in srd_frames.cpp, for every scenario that writes frames.
extern template void add_srd_frames<2>(Run&, const TriggerPtr&);
extern template void add_srd_frames<3>(Run&, const TriggerPtr&);

}  // namespace granflow::srd
