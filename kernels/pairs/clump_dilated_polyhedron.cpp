// Pair type clump-dilated polyhedron: each element against the core (GJK; sphere elements in closed
// form).
#include "../dilated_polyhedron/convex_pairs.hpp"

namespace kdem {

template void
compute_pair_type<ClumpFamily, DilatedPolyhedronFamily, HertzMindlin<false>>(const ContactContext&,
                                                                             PairTypeRows&);
template void
compute_pair_type<ClumpFamily, DilatedPolyhedronFamily, HertzMindlin<true>>(const ContactContext&,
                                                                            PairTypeRows&);

} // namespace kdem
