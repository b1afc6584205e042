#pragma once
// Starting a run from a stored state (initial.from, initial.frame; see
// engine/io/stored_state.hpp for the formats): the scenario's keys that the
// state determines are set from it before the run reads them, and the
// particles are put into the world as they were stored, each checked: inside
// the box (within tolerance at a wall), no two overlapping, the columns the
// run needs present.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "components/box.hpp"
#include "components/mass.hpp"
#include "components/particle_id.hpp"
#include "components/position.hpp"
#include "components/radius.hpp"
#include "components/species.hpp"
#include "components/velocity.hpp"
#include "engine/core/config.hpp"
#include "engine/core/input_error.hpp"
#include "engine/core/world.hpp"
#include "engine/io/stored_state.hpp"

namespace granflow {

inline void declare_stored_start_keys(ConfigSchema& schema) {
  schema
      .text("initial.from", "",
            "start from a stored state instead of placing particles: a granflow result file (H5MD), a GSD file "
            "(HOOMD schema) or an extended XYZ file; its box, particle count, radii, masses and velocities replace "
            "the system.* and initial.* settings (empty: place particles)")
      .integer("initial.frame", -1, -1000000000, 1000000000,
               "the frame of initial.from to start from (0 the first; negative counts from the end, -1 the last)");
}

inline bool starts_from_stored_state(const Config& config) {
  return config.schema().find("initial.from") && !config.text("initial.from").empty();
}

inline StoredState stored_state_of(const Config& config) {
  return read_stored_state(config.text("initial.from"), config.integer("initial.frame"));
}

// One value for every particle, or a refusal naming the key that holds one.
double uniform(const std::vector<double>& values, const std::string& what, const std::string& key,
               const StoredState& s);

// Sets system.dimension, count, box (system.box_length or system.box),
// boundary and the radius (system.* or particle.*), each where the scenario
// has the key, from the stored state `s`.
void adopt_stored_layout(Config& config, const StoredState& s);

// The layout and the one mass of every particle, where initial.from is set.
void adopt_stored_state(Config& config);

// The same for an ensemble of deterministic runs (event-driven dynamics):
// runs started from one stored state would repeat each other, so a stored
// start is one run (run.runs = 1), anything else refused.
void adopt_stored_state_as_one_run(Config& config);

// How far a stored state may depart from a hard-sphere one: soft spheres
// (DEM) may overlap a little and rest against walls inside the box.
struct StoredStateLimits {
  double overlap = 0.0;       // of the smaller radius
  bool radius_fits = true;    // along a closed axis, the whole sphere inside [0, L]
};

// Puts the stored particles into an empty world over a box of `edges` (the
// box the adopted configuration describes): positions (wrapped along
// `periodic` axes), velocities, radii and masses, refusing a particle
// outside the box or two that overlap beyond the limits.
// Compiled once for 2 and 3 dimensions (stored_start.cpp).
template <int D>
void place_stored_state(World& world, const std::array<double, D>& edges, const std::array<bool, D>& periodic,
                        const StoredState& s, const StoredStateLimits& limits = {});
extern template void place_stored_state<2>(World&, const std::array<double, 2>&, const std::array<bool, 2>&,
                                           const StoredState&, const StoredStateLimits&);
extern template void place_stored_state<3>(World&, const std::array<double, 3>&, const std::array<bool, 3>&,
                                           const StoredState&, const StoredStateLimits&);

// The same for point particles of one kind (SRD) over MPI ranks: only the
// particles `owns` (this rank's domain, by position) go into the world, in
// the stored order, each with its stored index as its ParticleId where the
// world has one. The frame is read block by block and every particle is
// checked, so that every rank refuses a bad state alike and none holds the
// whole.
template <int D>
void place_stored_part(World& world, const std::array<double, D>& edges, const std::array<bool, D>& periodic,
                       const StoredFrame& frame, const std::function<bool(const double* position)>& owns);
extern template void place_stored_part<2>(World&, const std::array<double, 2>&, const std::array<bool, 2>&,
                                          const StoredFrame&, const std::function<bool(const double*)>&);
extern template void place_stored_part<3>(World&, const std::array<double, 3>&, const std::array<bool, 3>&,
                                          const StoredFrame&, const std::function<bool(const double*)>&);

}  // namespace granflow
