// Pair type sphere-sphere (closed-form contact) and the sphere family's wall contacts.
#include "../families/pair_loop.hpp"

namespace kdem {

template <> struct NarrowPhase<SphereFamily, SphereFamily> : EveryRowOfTheType {
  static constexpr const char* label = "kdem::sphere_pair_forces";
  static constexpr bool tallied = false;
  static constexpr int max_contacts = 1;
  int team_size = 0;
  ParticleViews p;

  explicit NarrowPhase(const ContactContext& c) : p(c.particles) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<1>& found,
                                                NarrowPhaseTally&) const {
    const double ri = p.radius(r.i), rj = p.radius(r.j);
    PairContact& contact = found.contact[0];
    contact.geometry = sphere_sphere(load3(p.position, r.i), ri, load3(p.position, r.j), rj);
    if (!contact.geometry.touching)
      return PairOutcome::apart;
    contact.effective_radius = ri * rj / (ri + rj);
    found.count = 1;
    return PairOutcome::touching;
  }
};

template void
compute_pair_type<SphereFamily, SphereFamily, HertzMindlin<false>>(const ContactContext&,
                                                                   PairTypeRows&);
template void
compute_pair_type<SphereFamily, SphereFamily, HertzMindlin<true>>(const ContactContext&,
                                                                  PairTypeRows&);
template void compute_family_wall_contacts<SphereFamily, HertzMindlin<false>>(const ContactContext&,
                                                                              const RowSet&);
template void compute_family_wall_contacts<SphereFamily, HertzMindlin<true>>(const ContactContext&,
                                                                             const RowSet&);

} // namespace kdem
