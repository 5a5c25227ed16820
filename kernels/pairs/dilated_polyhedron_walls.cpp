// The dilated-polyhedron family's wall contacts: planes, cylinders and meshes.
#include "../dilated_polyhedron/walls.hpp"
#include "../families/pair_loop.hpp"

namespace kdem {

template void
compute_family_wall_contacts<DilatedPolyhedronFamily, HertzMindlin<false>>(const ContactContext&,
                                                                           const RowSet&);
template void
compute_family_wall_contacts<DilatedPolyhedronFamily, HertzMindlin<true>>(const ContactContext&,
                                                                          const RowSet&);

} // namespace kdem
