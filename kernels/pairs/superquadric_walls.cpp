// The superquadric family's wall contacts: planes, cylinders and meshes.
#include "../superquadric/walls.hpp"

namespace kdem {

template void
compute_family_wall_contacts<SuperquadricFamily, HertzMindlin<false>>(const ContactContext&,
                                                                      const RowSet&);
template void
compute_family_wall_contacts<SuperquadricFamily, HertzMindlin<true>>(const ContactContext&,
                                                                     const RowSet&);

} // namespace kdem
