#include "systems/srd/srd_setup.hpp"

namespace granflow::srd {

template void add_srd_fluid<2>(Run&, std::vector<Wall>, BodyForce<2>, bool);
template void add_srd_fluid<3>(Run&, std::vector<Wall>, BodyForce<3>, bool);

}  // namespace granflow::srd
