// Pair type poly-superquadric-poly-superquadric: prefilter, then the octant-pair midway-point
// Newton.
#include "../poly_superquadric/pairs.hpp"

namespace kdem {

template void
compute_pair_type<PolySuperquadricFamily, PolySuperquadricFamily, HertzMindlin<false>>(
    const ContactContext&, PairTypeRows&);
template void compute_pair_type<PolySuperquadricFamily, PolySuperquadricFamily, HertzMindlin<true>>(
    const ContactContext&, PairTypeRows&);

} // namespace kdem
