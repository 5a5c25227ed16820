// Pair type sphere-sphere (closed-form contact) and the sphere family's wall contacts.
#include "../families/pair_loop.hpp"
#include "../force_sum.hpp"

namespace kdem {

template <> struct NarrowPhase<SphereFamily, SphereFamily> : EveryRowOfTheType {
  static constexpr const char* label = "kdem::sphere_pair_forces";
  static constexpr bool tallied = false;
  static constexpr int max_contacts = 1;
  int team_size = 0;
  ParticleViews p;

  explicit NarrowPhase(const ContactContext& c) : p(c.particles) {}

  // The contact of spheres (xi, ri) and (xj, rj); false when apart.
  KOKKOS_INLINE_FUNCTION static bool contact_of(Vec3 xi, double ri, Vec3 xj, double rj,
                                                PairContact& contact) {
    contact.geometry = sphere_sphere(xi, ri, xj, rj);
    if (!contact.geometry.touching)
      return false;
    contact.effective_radius = ri * rj / (ri + rj);
    return true;
  }

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<1>& found,
                                                NarrowPhaseTally&) const {
    if (!contact_of(load3(p.position, r.i), p.radius(r.i), load3(p.position, r.j), p.radius(r.j),
                    found.contact[0]))
      return PairOutcome::apart;
    found.count = 1;
    return PairOutcome::touching;
  }
};

template <class Law> void compute_sphere_rows(const ContactContext& c, Vec3 gravity) {
  using Narrow = NarrowPhase<SphereFamily, SphereFamily>;
  const PairSlots slots(c.pairs);
  const ParticleViews p = c.particles;
  const GravityAndWallTerms first_terms(p, gravity, c.wall_contacts);
  auto row_start = c.pairs.row_start, pair_j = c.pairs.pair_j;
  const CoefficientTable table = c.coefficients;
  const double dt = c.dt;
  Kokkos::parallel_for(
      "kdem::sphere_rows", RangePolicy(0, p.count), KOKKOS_LAMBDA(int i) {
        Vec3 f, t;
        first_terms.start(i, f, t);
        const BodyMotion bi = body_motion(p, i);
        const double ri = p.radius(i);
        const int material_i = p.material(i);
        for (int k = row_start(i); k < row_start(i + 1); ++k) {
          const int j = pair_j(k);
          PairContact contact;
          Vec3 pair_force{}, pair_torque{};
          if (Narrow::contact_of(bi.centre, ri, load3(p.position, j), p.radius(j), contact))
            slots.template apply<Law>(k, bi, body_motion(p, j), contact.geometry,
                                      contact.effective_radius, table(material_i, p.material(j)),
                                      dt, pair_force, pair_torque);
          else
            slots.clear(k); // force and torque stored zero, as added here
          f += pair_force;
          t += pair_torque;
        }
        store3(p.force, i, f);
        store3(p.torque, i, t);
      });
}

template void
compute_pair_type<SphereFamily, SphereFamily, HertzMindlin<false>>(const ContactContext&,
                                                                   PairTypeRows&);
template void
compute_pair_type<SphereFamily, SphereFamily, HertzMindlin<true>>(const ContactContext&,
                                                                  PairTypeRows&);
template void compute_sphere_rows<HertzMindlin<false>>(const ContactContext&, Vec3);
template void compute_sphere_rows<HertzMindlin<true>>(const ContactContext&, Vec3);
template void compute_family_wall_contacts<SphereFamily, HertzMindlin<false>>(const ContactContext&,
                                                                              const RowSet&);
template void compute_family_wall_contacts<SphereFamily, HertzMindlin<true>>(const ContactContext&,
                                                                             const RowSet&);

} // namespace kdem
