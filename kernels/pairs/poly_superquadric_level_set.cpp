// Pair type poly-superquadric-level set: the level-set body's points against the octants' closest
// point, the body's deepest point in the grid.
#include "../level_set/mixed_pairs.hpp"

namespace kdem {

template void compute_pair_type<PolySuperquadricFamily, LevelSetFamily, HertzMindlin<false>>(
    const ContactContext&, PairTypeRows&);
template void
compute_pair_type<PolySuperquadricFamily, LevelSetFamily, HertzMindlin<true>>(const ContactContext&,
                                                                              PairTypeRows&);

} // namespace kdem
