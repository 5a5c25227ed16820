// Pair type poly-superquadric-dilated polyhedron: the poly-superquadric's support against the
// core's faces (GJK).
#include "../dilated_polyhedron/convex_pairs.hpp"

namespace kdem {

template void
compute_pair_type<PolySuperquadricFamily, DilatedPolyhedronFamily, HertzMindlin<false>>(
    const ContactContext&, PairTypeRows&);
template void
compute_pair_type<PolySuperquadricFamily, DilatedPolyhedronFamily, HertzMindlin<true>>(
    const ContactContext&, PairTypeRows&);

} // namespace kdem
