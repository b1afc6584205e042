// Linked into every test program: keeps the built-in scenarios (and their
// registrations) in it, as the granflow program does.
#include "engine/app/cli.hpp"

namespace {
const bool linked = (granflow::link_builtin_scenarios(), true);
}
