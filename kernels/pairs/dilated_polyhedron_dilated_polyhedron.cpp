// Pair type dilated polyhedron-dilated polyhedron: the local minima of the core distance.
#include "../dilated_polyhedron/pairs.hpp"

namespace kdem {

template void
compute_pair_type<DilatedPolyhedronFamily, DilatedPolyhedronFamily, HertzMindlin<false>>(
    const ContactContext&, PairTypeRows&);
template void
compute_pair_type<DilatedPolyhedronFamily, DilatedPolyhedronFamily, HertzMindlin<true>>(
    const ContactContext&, PairTypeRows&);

} // namespace kdem
