// Pair type dilated polyhedron-level set: the level-set body's points within the core's dilation,
// the core's vertices and edge samples in the grid.
#include "../level_set/mixed_pairs.hpp"

namespace kdem {

template void compute_pair_type<DilatedPolyhedronFamily, LevelSetFamily, HertzMindlin<false>>(
    const ContactContext&, PairTypeRows&);
template void compute_pair_type<DilatedPolyhedronFamily, LevelSetFamily, HertzMindlin<true>>(
    const ContactContext&, PairTypeRows&);

} // namespace kdem
