#pragma once
// The event counts and the energy dissipated in an event-driven run, as
// attributes of /observables: pair_collisions, wall_collisions,
// pair_dissipated_energy, wall_dissipated_energy and their sum
// dissipated_energy.

#include "engine/io/h5md_file.hpp"
#include "systems/edmd/event_driven_gas.hpp"

namespace granflow::edmd {

inline void write_event_statistics(H5mdFile& file, const EventStatistics& stats) {
  file.write_attribute("/observables", "pair_collisions", static_cast<double>(stats.pair_collisions));
  file.write_attribute("/observables", "wall_collisions", static_cast<double>(stats.wall_collisions));
  file.write_attribute("/observables", "pair_dissipated_energy", stats.dissipated_energy);
  file.write_attribute("/observables", "wall_dissipated_energy", stats.wall_dissipated_energy);
  file.write_attribute("/observables", "dissipated_energy", stats.dissipated_energy + stats.wall_dissipated_energy);
}

}  // namespace granflow::edmd
