// Pair type superquadric-dilated polyhedron: the superquadric's support against the core's faces
// (GJK).
#include "../dilated_polyhedron/convex_pairs.hpp"

namespace kdem {

template void compute_pair_type<SuperquadricFamily, DilatedPolyhedronFamily, HertzMindlin<false>>(
    const ContactContext&, PairTypeRows&);
template void compute_pair_type<SuperquadricFamily, DilatedPolyhedronFamily, HertzMindlin<true>>(
    const ContactContext&, PairTypeRows&);

} // namespace kdem
