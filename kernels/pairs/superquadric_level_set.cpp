// Pair type superquadric-level set: the level-set body's points against the superquadric's closest
// point, the superquadric's deepest point in the grid.
#include "../level_set/mixed_pairs.hpp"

namespace kdem {

template void
compute_pair_type<SuperquadricFamily, LevelSetFamily, HertzMindlin<false>>(const ContactContext&,
                                                                           PairTypeRows&);
template void
compute_pair_type<SuperquadricFamily, LevelSetFamily, HertzMindlin<true>>(const ContactContext&,
                                                                          PairTypeRows&);

} // namespace kdem
