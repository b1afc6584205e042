// Must not compile: a view that only reads Mass handed to a helper whose
// view writes it (CMake runs the compiler on this file and expects the
// View's message).

#include "components/mass.hpp"
#include "engine/core/view.hpp"

namespace granflow {

void scale_masses(View<Reads<>, Writes<Mass>> view) { view.write<Mass>()[0] *= 2.0; }

void caller(World& world) {
  View<Reads<Mass>, Writes<>> view(world);
  scale_masses(view);
}

}  // namespace granflow
