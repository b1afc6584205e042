#include "systems/srd/srd_frames.hpp"

namespace granflow::srd {

template void add_srd_frames<2>(Run&, const TriggerPtr&);
template void add_srd_frames<3>(Run&, const TriggerPtr&);

}  // namespace granflow::srd
