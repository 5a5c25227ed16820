// Pair type clump-clump: every element pair within reach.
#include "../clump/pairs.hpp"

namespace kdem {

template void
compute_pair_type<ClumpFamily, ClumpFamily, HertzMindlin<false>>(const ContactContext&,
                                                                 PairTypeRows&);
template void compute_pair_type<ClumpFamily, ClumpFamily, HertzMindlin<true>>(const ContactContext&,
                                                                              PairTypeRows&);

} // namespace kdem
