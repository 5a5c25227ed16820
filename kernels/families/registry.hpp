#pragma once
// The engine's particle families, written once. Pair types, their rows and kernels, template
// tables and counts follow from this list (family_list.hpp); each family's own files hold its
// trait, template table, narrow phases against the families before it, and wall contact.
// A new family is added here, at the end of the list (docs/architecture.md, "Adding a shape
// family").
#include "../clump/family.hpp"
#include "../dilated_polyhedron/family.hpp"
#include "../level_set/family.hpp"
#include "../poly_superquadric/family.hpp"
#include "../superquadric/family.hpp"
#include <type_traits>

#include "contact_context.hpp"
#include "sphere.hpp"

namespace kdem {

using Families = FamilyList<SphereFamily, SuperquadricFamily, PolySuperquadricFamily, ClumpFamily,
                            DilatedPolyhedronFamily, LevelSetFamily>;
using ContactContext = ContactContextOf<Families>;
using EngineFamilyRows = FamilyRows<Families>;

// Pair types whose narrow phase is not written: no kernel exists for them, and the engine refuses
// a scene whose shapes hold both families (Engine::State::setup_shapes). Every pair type of the
// six families is written; a new family declares its missing ones here, as false_type.
template <class A, class B> struct pair_type_implemented : std::true_type {};

// The typed kernels, declared here and instantiated once per pair type and per family in the
// translation units of kernels/pairs/ (so that they compile in parallel, and the engine's own
// translation unit compiles none of them).
template <class A, class B, class Law>
void compute_pair_type(const ContactContext& c, PairTypeRows& rows);
template <class F, class Law>
void compute_family_wall_contacts(const ContactContext& c, const RowSet& rows);

// Bit f set: some particle is of family f.
inline int present_families(const ParticleViews& p, const ShapeFamilies& shapes) {
  auto shape = p.shape;
  int mask = 0;
  Kokkos::parallel_reduce(
      "kdem::present_families", RangePolicy(0, p.count),
      KOKKOS_LAMBDA(int i, int& m) { m |= 1 << shapes.family(shape(i)); }, Kokkos::BOr<int>(mask));
  return mask;
}

template <class Visit> void for_each_present_family(int mask, Visit&& visit) {
  for_each_family<Families>([&](auto tag) {
    using F = typename decltype(tag)::type;
    if (mask & (1 << family_index_v<F, Families>))
      visit(tag);
  });
}

// The families of `mask` with some property: any_family(mask, [](auto tag) { ... }).
template <class Test> bool any_present_family(int mask, Test&& test) {
  bool any = false;
  for_each_present_family(mask, [&](auto tag) { any = any || test(tag); });
  return any;
}

} // namespace kdem
