// Must not compile: a system's view reads a column it does not declare
// (CMake runs the compiler on this file and expects the View's message).

#include "components/mass.hpp"
#include "components/velocity.hpp"
#include "engine/core/view.hpp"

namespace granflow {

double undeclared(World& world) {
  View<Reads<Velocity<3>>, Writes<>> view(world);
  return view.read<Mass>()[0];
}

}  // namespace granflow
