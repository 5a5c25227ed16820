// Pair type superquadric-poly-superquadric: the octant search with the midway-point Newton.
#include "../poly_superquadric/pairs.hpp"

namespace kdem {

template void compute_pair_type<SuperquadricFamily, PolySuperquadricFamily, HertzMindlin<false>>(
    const ContactContext&, PairTypeRows&);
template void compute_pair_type<SuperquadricFamily, PolySuperquadricFamily, HertzMindlin<true>>(
    const ContactContext&, PairTypeRows&);

} // namespace kdem
