#include "systems/srd/srd_watchdog.hpp"

namespace granflow::srd {

template void observe_state<2>(Run&, const TriggerPtr&);
template void observe_state<3>(Run&, const TriggerPtr&);

}  // namespace granflow::srd
