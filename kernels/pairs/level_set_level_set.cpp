// Pair type level set-level set: each body's surface points in the other's grid.
#include "../level_set/pairs.hpp"

namespace kdem {

template void
compute_pair_type<LevelSetFamily, LevelSetFamily, HertzMindlin<false>>(const ContactContext&,
                                                                       PairTypeRows&);
template void
compute_pair_type<LevelSetFamily, LevelSetFamily, HertzMindlin<true>>(const ContactContext&,
                                                                      PairTypeRows&);

} // namespace kdem
