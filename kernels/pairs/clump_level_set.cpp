// Pair type clump-level set: each element within reach as a sphere or superquadric piece against
// the level-set body.
#include "../level_set/mixed_pairs.hpp"

namespace kdem {

template void
compute_pair_type<ClumpFamily, LevelSetFamily, HertzMindlin<false>>(const ContactContext&,
                                                                    PairTypeRows&);
template void
compute_pair_type<ClumpFamily, LevelSetFamily, HertzMindlin<true>>(const ContactContext&,
                                                                   PairTypeRows&);

} // namespace kdem
