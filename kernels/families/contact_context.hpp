#pragma once
// What the typed contact kernels of one step read and write, for a list of families: the
// stores, the coefficients, each family's template table and the narrow-phase counters. Host
// side only: each kernel copies out the Views and the one table it needs.
#include <tuple>

#include "../contact_law.hpp"
#include "../pair_list.hpp"
#include "../walls.hpp"
#include "family_rows.hpp"
#include "narrow_phase_tally.hpp"

namespace kdem {

template <class List> struct FamilyTablesOf;
template <class... Families> struct FamilyTablesOf<FamilyList<Families...>> {
  using type = std::tuple<typename Families::Table...>;
};

template <class List> struct ContactContextOf {
  using Tables = typename FamilyTablesOf<List>::type;
  ParticleViews particles;
  PairList pairs;
  WallSet walls;
  WallContactList wall_contacts;
  CoefficientTable coefficients;
  ShapeFamilies shape_families;
  Tables tables;
  NarrowPhaseCounters counters;
  double dt = 0;
  double surface_travel = 0; // m, see Engine::State::surface_travel

  template <class F> const typename F::Table& table() const {
    return std::get<family_index_v<F, List>>(tables);
  }
  template <class F> typename F::Table& table() {
    return std::get<family_index_v<F, List>>(tables);
  }
};

} // namespace kdem
