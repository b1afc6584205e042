#include "systems/srd/srd_fields.hpp"

namespace granflow::srd {

template void add_srd_fields<2>(Run&, std::array<std::int32_t, 2>);
template void add_srd_fields<3>(Run&, std::array<std::int32_t, 3>);

}  // namespace granflow::srd
