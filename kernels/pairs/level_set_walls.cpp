// The level-set family's wall contacts: planes, cylinders and meshes.
#include "../families/pair_loop.hpp"
#include "../level_set/walls.hpp"

namespace kdem {

template void
compute_family_wall_contacts<LevelSetFamily, HertzMindlin<false>>(const ContactContext&,
                                                                  const RowSet&);
template void
compute_family_wall_contacts<LevelSetFamily, HertzMindlin<true>>(const ContactContext&,
                                                                 const RowSet&);

} // namespace kdem
