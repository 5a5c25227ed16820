// Pair type superquadric-superquadric: prefilter, then the midway-point Newton narrow phase.
#include "../superquadric/pairs.hpp"

namespace kdem {

template void compute_pair_type<SuperquadricFamily, SuperquadricFamily, HertzMindlin<false>>(
    const ContactContext&, PairTypeRows&);
template void
compute_pair_type<SuperquadricFamily, SuperquadricFamily, HertzMindlin<true>>(const ContactContext&,
                                                                              PairTypeRows&);

} // namespace kdem
