// Pair type sphere-dilated polyhedron: the sphere's centre against the core's features.
#include "../dilated_polyhedron/pairs.hpp"

namespace kdem {

template void
compute_pair_type<SphereFamily, DilatedPolyhedronFamily, HertzMindlin<false>>(const ContactContext&,
                                                                              PairTypeRows&);
template void
compute_pair_type<SphereFamily, DilatedPolyhedronFamily, HertzMindlin<true>>(const ContactContext&,
                                                                             PairTypeRows&);

} // namespace kdem
