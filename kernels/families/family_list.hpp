#pragma once
// Compile-time lists of particle families and the pair types they make. A family is a type
// with a small trait (see docs/architecture.md, "Adding a shape family"); the list of the
// engine's families is written once, in registry.hpp, and everything indexed by family or by
// pair type (index lists, kernels, counts) follows from it here.
#include <Kokkos_Macros.hpp>
#include <type_traits>
#include <utility>

namespace kdem {

template <class... Families> struct FamilyList {
  static constexpr int size = int(sizeof...(Families));
};

// Stands for family F where a value is wanted (for_each_family passes one).
template <class F> struct FamilyTag { using type = F; };

namespace detail {
template <class F, class... Rest> constexpr int index_in_pack() {
  constexpr bool same[] = {std::is_same_v<F, Rest>...};
  for (int k = 0; k < int(sizeof...(Rest)); ++k)
    if (same[k])
      return k;
  return -1;
}
} // namespace detail

template <class F, class List> struct family_index;
template <class F, class... Families> struct family_index<F, FamilyList<Families...>> {
  static constexpr int value = detail::index_in_pack<F, Families...>();
  static_assert(value >= 0, "not a family of this list");
};
template <class F, class List> constexpr int family_index_v = family_index<F, List>::value;

template <int K, class List> struct family_at;
template <int K, class First, class... Rest> struct family_at<K, FamilyList<First, Rest...>> {
  using type = typename family_at<K - 1, FamilyList<Rest...>>::type;
};
template <class First, class... Rest> struct family_at<0, FamilyList<First, Rest...>> {
  using type = First;
};
template <int K, class List> using family_at_t = typename family_at<K, List>::type;

// Unordered pairs {a, b} of n families, a <= b, numbered row by row:
// (0,0), (0,1), ..., (0,n-1), (1,1), ..., (n-1,n-1).
constexpr int pair_type_count(int n) {
  return n * (n + 1) / 2;
}

// Device-callable: the kernels that sort pairs by type call it.
KOKKOS_INLINE_FUNCTION constexpr int pair_type_index(int a, int b, int n) {
  if (a > b) {
    const int t = a;
    a = b;
    b = t;
  }
  return a * n - a * (a - 1) / 2 + (b - a);
}

template <class A, class B, class List>
constexpr int pair_type_index_v = pair_type_index(family_index_v<A, List>, family_index_v<B, List>,
                                                  List::size);

namespace detail {
template <class List, class Visit, int... K>
void visit_families(Visit& visit, std::integer_sequence<int, K...>) {
  (visit(FamilyTag<family_at_t<K, List>>{}), ...);
}

template <class List, int A, class Visit, int... B>
void visit_partners(Visit& visit, std::integer_sequence<int, B...>) {
  (visit(FamilyTag<family_at_t<A, List>>{}, FamilyTag<family_at_t<A + B, List>>{}), ...);
}

template <class List, class Visit, int... A>
void visit_pair_types(Visit& visit, std::integer_sequence<int, A...>) {
  (visit_partners<List, A>(visit, std::make_integer_sequence<int, List::size - A>{}), ...);
}
} // namespace detail

// visit(FamilyTag<F>{}) for each family F of the list, in list order.
template <class List, class Visit> void for_each_family(Visit&& visit) {
  detail::visit_families<List>(visit, std::make_integer_sequence<int, List::size>{});
}

// visit(FamilyTag<A>{}, FamilyTag<B>{}) for each pair type, A not after B in the list, in the
// order of pair_type_index.
template <class List, class Visit> void for_each_pair_type(Visit&& visit) {
  detail::visit_pair_types<List>(visit, std::make_integer_sequence<int, List::size>{});
}

} // namespace kdem
