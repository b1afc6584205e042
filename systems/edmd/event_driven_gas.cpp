// The event-driven engine's one instantiation for disks and for spheres. It is
// compiled like the contact search (CMakeLists.txt): for the kernels'
// instruction set, with no contracted multiply-adds and no errno or trapping
// math, so the event loop gets the wider instructions (rounding, division,
// minimum image) while every floating-point result stays bit for bit what a
// baseline build computes.
#include "systems/edmd/event_driven_gas.hpp"

namespace granflow::edmd {

template class EventDrivenGas<2>;
template class EventDrivenGas<3>;

}  // namespace granflow::edmd
