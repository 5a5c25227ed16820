// Pair type superquadric-clump: the superquadric against each element within reach.
#include "../clump/pairs.hpp"

namespace kdem {

template void
compute_pair_type<SuperquadricFamily, ClumpFamily, HertzMindlin<false>>(const ContactContext&,
                                                                        PairTypeRows&);
template void
compute_pair_type<SuperquadricFamily, ClumpFamily, HertzMindlin<true>>(const ContactContext&,
                                                                       PairTypeRows&);

} // namespace kdem
