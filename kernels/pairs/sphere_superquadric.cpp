// Pair type sphere-superquadric: the closest point of the superquadric to the sphere centre.
#include "../superquadric/pairs.hpp"

namespace kdem {

template void
compute_pair_type<SphereFamily, SuperquadricFamily, HertzMindlin<false>>(const ContactContext&,
                                                                         PairTypeRows&);
template void
compute_pair_type<SphereFamily, SuperquadricFamily, HertzMindlin<true>>(const ContactContext&,
                                                                        PairTypeRows&);

} // namespace kdem
