// Pair type sphere-level set: the sphere's centre in the body's grid, or the body's surface
// points in the sphere.
#include "../level_set/pairs.hpp"

namespace kdem {

template void
compute_pair_type<SphereFamily, LevelSetFamily, HertzMindlin<false>>(const ContactContext&,
                                                                     PairTypeRows&);
template void
compute_pair_type<SphereFamily, LevelSetFamily, HertzMindlin<true>>(const ContactContext&,
                                                                    PairTypeRows&);

} // namespace kdem
