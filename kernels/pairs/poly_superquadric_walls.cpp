// The poly-superquadric family's wall contacts: planes, cylinders and meshes.
#include "../poly_superquadric/walls.hpp"

namespace kdem {

template void
compute_family_wall_contacts<PolySuperquadricFamily, HertzMindlin<false>>(const ContactContext&,
                                                                          const RowSet&);
template void
compute_family_wall_contacts<PolySuperquadricFamily, HertzMindlin<true>>(const ContactContext&,
                                                                         const RowSet&);

} // namespace kdem
