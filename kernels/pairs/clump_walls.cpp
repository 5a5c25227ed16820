// The clump family's wall contacts: planes, cylinders and meshes, per element.
#include "../clump/walls.hpp"

namespace kdem {

template void compute_family_wall_contacts<ClumpFamily, HertzMindlin<false>>(const ContactContext&,
                                                                             const RowSet&);
template void compute_family_wall_contacts<ClumpFamily, HertzMindlin<true>>(const ContactContext&,
                                                                            const RowSet&);

} // namespace kdem
