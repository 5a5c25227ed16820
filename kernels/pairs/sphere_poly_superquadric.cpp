// Pair type sphere-poly-superquadric: the closest point of the octant elements to the sphere
// centre.
#include "../poly_superquadric/pairs.hpp"

namespace kdem {

template void
compute_pair_type<SphereFamily, PolySuperquadricFamily, HertzMindlin<false>>(const ContactContext&,
                                                                             PairTypeRows&);
template void
compute_pair_type<SphereFamily, PolySuperquadricFamily, HertzMindlin<true>>(const ContactContext&,
                                                                            PairTypeRows&);

} // namespace kdem
