// Pair type poly-superquadric-clump: the poly-superquadric against each element within reach.
#include "../clump/pairs.hpp"

namespace kdem {

template void
compute_pair_type<PolySuperquadricFamily, ClumpFamily, HertzMindlin<false>>(const ContactContext&,
                                                                            PairTypeRows&);
template void
compute_pair_type<PolySuperquadricFamily, ClumpFamily, HertzMindlin<true>>(const ContactContext&,
                                                                           PairTypeRows&);

} // namespace kdem
