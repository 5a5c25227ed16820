// Pair type sphere-clump: the sphere against each element within reach.
#include "../clump/pairs.hpp"

namespace kdem {

template void
compute_pair_type<SphereFamily, ClumpFamily, HertzMindlin<false>>(const ContactContext&,
                                                                  PairTypeRows&);
template void
compute_pair_type<SphereFamily, ClumpFamily, HertzMindlin<true>>(const ContactContext&,
                                                                 PairTypeRows&);

} // namespace kdem
