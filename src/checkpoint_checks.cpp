// The consistency of a state read from a checkpoint, checked before the engine takes it: every
// index a kernel follows stays inside the View it indexes, every offset table is a valid
// partition, every per-particle value is one the engine could have produced. A file that fails
// is refused with the dataset and the rule it breaks; nothing of it is kept.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine_state.hpp"

namespace kdem {

// Instantiated in engine.cpp alone: a template holding a KOKKOS_LAMBDA must be compiled in one
// unit of a CUDA build (scripts/check_cuda_lambdas.sh).
extern template void assign_slots_by_pair_type<Families>(PairList&, const ParticleViews&,
                                                         const ShapeFamilies&, int);
extern template void assign_wall_slots_by_family<Families>(WallContactList&, const ParticleViews&,
                                                           const ShapeFamilies&, int);
namespace {

template <class View> auto host_copy(const View& view) {
  return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view);
}

class RestoreCheck {
public:
  explicit RestoreCheck(const std::string& path) : path_(path) {}

  void require(bool ok, const std::string& what) const {
    if (!ok)
      throw std::runtime_error(path_ + ": checkpoint is inconsistent: " + what);
  }

  template <class View> void rows(const std::string& name, const View& view, long expected) const {
    require(long(view.extent(0)) == expected, name + " has " + std::to_string(view.extent(0)) +
                                                  " rows, expected " + std::to_string(expected));
  }

  // Rows of an optional field: `expected` where the engine needs it, else `expected` or none.
  template <class View>
  void optional_rows(const std::string& name, const View& view, long expected, bool needed) const {
    if (needed || view.extent(0) != 0)
      rows(name, view, expected);
  }

  // offsets(0) = 0, non-decreasing, offsets(entries) = total: rows of a table in order.
  void offsets(const std::string& name, const IndexView& view, long entries, long total) const {
    rows(name, view, entries + 1);
    const auto h = host_copy(view);
    require(h(0) == 0, name + " does not start at 0");
    for (long k = 0; k < entries; ++k)
      require(h(k + 1) >= h(k), name + " decreases at row " + std::to_string(k + 1));
    require(h(entries) == total, name + " ends at " + std::to_string(h(entries)) + ", expected " +
                                     std::to_string(total));
  }

  template <class View>
  void indices(const std::string& name, const View& view, long lo, long hi) const {
    const auto h = host_copy(view);
    for (std::size_t k = 0; k < h.extent(0); ++k)
      require(h(k) >= lo && h(k) < hi, name + " row " + std::to_string(k) + " is " +
                                           std::to_string(h(k)) + ", outside [" +
                                           std::to_string(lo) + ", " + std::to_string(hi) + ")");
  }

  template <class View> void finite(const std::string& name, const View& view) const {
    const auto h = host_copy(view);
    for (std::size_t k = 0; k < h.extent(0); ++k)
      for (std::size_t c = 0; c < (View::rank == 1 ? 1 : h.extent(1)); ++c)
        require(std::isfinite(value_at(h, k, c)),
                name + " row " + std::to_string(k) + " is not finite");
  }

  void positive(const std::string& name, const ScalarView& view) const {
    const auto h = host_copy(view);
    for (std::size_t k = 0; k < h.extent(0); ++k)
      require(h(k) > 0, name + " row " + std::to_string(k) + " is not positive");
  }

  void unique(const std::string& name, const IdView& view) const {
    const auto h = host_copy(view);
    std::vector<std::int64_t> sorted(h.data(), h.data() + h.extent(0));
    std::sort(sorted.begin(), sorted.end());
    require(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end(),
            name + " holds an id twice");
  }

  template <class A, class B>
  void same(const std::string& what, const A& loaded, const B& derived) const {
    const auto a = host_copy(loaded);
    const auto b = host_copy(derived);
    bool equal = a.extent(0) == b.extent(0);
    for (std::size_t k = 0; equal && k < a.extent(0); ++k)
      equal = a(k) == b(k);
    require(equal, what);
  }

private:
  template <class Host> static double value_at(const Host& h, std::size_t k, std::size_t c) {
    if constexpr (Host::rank == 1)
      return double(h(k));
    else
      return double(h(k, c));
  }

  std::string path_;
};

// Row r of every entry of a table with offsets `start` (r such that start(r) <= k < start(r+1)).
template <class HostOffsets>
bool entries_follow_rows(const HostOffsets& start, long rows, const IndexView& row_of_entry) {
  const auto owner = host_copy(row_of_entry);
  for (long r = 0; r < rows; ++r)
    for (int k = start(r); k < start(r + 1); ++k)
      if (owner(k) != r)
        return false;
  return true;
}

void check_particles(const RestoreCheck& check, const ParticleViews& p, std::int64_t next_id,
                     int materials, int shapes, int sources, int tags) {
  const long n = p.count;
  for_each_particle_field([&](const char* name, auto member) {
    check.rows(std::string("particles/") + name, p.*member, n);
  });
  check.indices("particles/material", p.material, 0, materials);
  check.indices("particles/shape", p.shape, 0, shapes);
  check.indices("particles/source", p.source, -1, sources);
  check.indices("particles/tag", p.tag, -1, tags);
  check.indices("particles/id", p.id, 0, next_id);
  check.unique("particles/id", p.id);
  check.finite("particles/position", p.position);
  check.finite("particles/velocity", p.velocity);
  check.finite("particles/angular_velocity", p.angular_velocity);
  check.finite("particles/orientation", p.orientation);
  check.finite("particles/force", p.force);
  check.finite("particles/torque", p.torque);
  check.finite("particles/radius", p.radius);
  check.finite("particles/mass", p.mass);
  check.finite("particles/inertia", p.inertia);
  check.finite("particles/position_at_build", p.position_at_build);
  check.finite("particles/turned_angle", p.turned_angle);
  check.positive("particles/radius", p.radius);
  check.positive("particles/mass", p.mass);
}

// What the lists are checked against.
struct ListContext {
  const ParticleViews& particles;
  const ShapeFamilies& shapes;
  int families_present;
  bool rolling;            // rolling-resistance history kept
  bool narrow_phase_state; // warm starts and separation certificates kept
  bool rebuild_due;        // lists of an older particle order, used only to carry history over
  long built;              // particles at the build of the lists
  int wall_elements;
  double surface_travel; // see Engine::State::surface_travel
};

// A certificate holds by the surface travel at most until half its gap is used up
// (SeparationCertificates): a larger expiry would let a pair pass through its partner.
void check_certificate_expiries(const RestoreCheck& check, const PairList& l, double travel) {
  if (l.separation_expiry.extent(0) == 0 || l.separation_margin.extent(0) == 0)
    return;
  const auto expiry = host_copy(l.separation_expiry);
  const auto margin = host_copy(l.separation_margin);
  check.require(std::isfinite(travel) && travel >= 0, "surface_travel is not a finite length");
  for (std::size_t k = 0; k < expiry.extent(0); ++k)
    if (!(expiry(k) == 0 || expiry(k) <= travel + 0.5 * margin(k)))
      check.require(false, "pairs/separation_expiry of row " + std::to_string(k) +
                               " beyond surface_travel + half its pairs/separation_margin");
}

// What both lists keep per contact slot: the slots of their entries (one each, or the partition
// contact_start gives), the spring, the rolling torque where the scene has rolling resistance and
// the overlap, all finite.
template <class List>
void check_slot_history(const RestoreCheck& check, const std::string& list, const List& l,
                        bool one_slot_each, long entries, bool rolling) {
  const long slots = l.slot_count;
  if (one_slot_each)
    check.require(slots == entries, list + "/overlap has " + std::to_string(slots) +
                                        " rows, expected one per entry (" +
                                        std::to_string(entries) + ")");
  else
    check.offsets(list + "/contact_start", l.contact_start, entries, slots);
  check.rows(list + "/tangential_spring", l.tangential_spring, slots);
  check.optional_rows(list + "/rolling_torque", l.rolling_torque, slots, rolling);
  check.finite(list + "/tangential_spring", l.tangential_spring);
  check.finite(list + "/rolling_torque", l.rolling_torque);
  check.finite(list + "/overlap", l.overlap);
}

void check_pairs(const RestoreCheck& check, const PairList& l, const ListContext& c) {
  const long count = l.pair_count;
  check.offsets("pairs/row_start", l.row_start, c.built, count);
  check.rows("pairs/pair_i", l.pair_i, count);
  check.rows("pairs/pair_j", l.pair_j, count);
  check.rows("pairs/partner_id", l.partner_id, count);
  check.require(entries_follow_rows(host_copy(l.row_start), c.built, l.pair_i),
                "pairs/pair_i does not follow pairs/row_start");
  check.indices("pairs/pair_j", l.pair_j, 0, c.built);
  check.offsets("pairs/reverse_start", l.reverse_start, c.built, count);
  check.rows("pairs/reverse_pair", l.reverse_pair, count);
  check.indices("pairs/reverse_pair", l.reverse_pair, 0, count);
  if (!c.rebuild_due) {
    PairList derived = l;
    fill_reverse_index(derived, int(c.built));
    check.same("pairs/reverse_start is not the reverse of pairs/pair_j", l.reverse_start,
               derived.reverse_start);
    check.same("pairs/reverse_pair is not the reverse of pairs/pair_j", l.reverse_pair,
               derived.reverse_pair);
    derived.contact_start = IndexView();
    assign_slots_by_pair_type<Families>(derived, c.particles, c.shapes, c.families_present);
    check.same("pairs/contact_start is not what the pair types give", l.contact_start,
               derived.contact_start);
  }
  check_slot_history(check, "pairs", l, l.one_slot_per_pair(), count, c.rolling);
  const long slots = l.slot_count;
  check.optional_rows("pairs/feature_i", l.feature_i, slots, !l.one_slot_per_pair());
  check.optional_rows("pairs/feature_j", l.feature_j, slots, !l.one_slot_per_pair());
  check.rows("pairs/force_on_i", l.force_on_i, count);
  check.rows("pairs/torque_on_i", l.torque_on_i, count);
  const bool narrow = c.narrow_phase_state;
  check.optional_rows("pairs/midway_point", l.midway_point, slots, narrow);
  check.optional_rows("pairs/midway_multiplier", l.midway_multiplier, slots, narrow);
  check.optional_rows("pairs/midway_step", l.midway_step, slots, narrow);
  check.optional_rows("pairs/separating_axis", l.separating_axis, count, narrow);
  check.optional_rows("pairs/separation_margin", l.separation_margin, count, narrow);
  check.optional_rows("pairs/separation_offset", l.separation_offset, count, narrow);
  check.optional_rows("pairs/turned_i_at_separation", l.turned_i_at_separation, count, narrow);
  check.optional_rows("pairs/turned_j_at_separation", l.turned_j_at_separation, count, narrow);
  check.optional_rows("pairs/separation_expiry", l.separation_expiry, count, narrow);
  check_certificate_expiries(check, l, c.surface_travel);
}

void check_wall_contacts(const RestoreCheck& check, const WallContactList& l,
                         const ListContext& c) {
  const long count = l.entry_count;
  check.offsets("wall_contacts/row_start", l.row_start, c.built, count);
  check.rows("wall_contacts/element", l.element, count);
  check.rows("wall_contacts/element_key", l.element_key, count);
  check.indices("wall_contacts/element", l.element, 0, c.wall_elements);
  if (!c.rebuild_due) {
    WallContactList derived = l;
    derived.contact_start = IndexView();
    assign_wall_slots_by_family<Families>(derived, c.particles, c.shapes, c.families_present);
    check.same("wall_contacts/contact_start is not what the families give", l.contact_start,
               derived.contact_start);
  }
  check_slot_history(check, "wall_contacts", l, l.one_slot_per_entry(), count, c.rolling);
  check.optional_rows("wall_contacts/feature", l.feature, l.slot_count, !l.one_slot_per_entry());
}

} // namespace

void Engine::State::check_restored_particles(const std::string& path) const {
  const RestoreCheck check(path);
  const long n = particles.count;
  constexpr std::int64_t most = std::int64_t(1) << 62;
  check.require(discharged_count < most && lost_count < most &&
                    next_id == n + discharged_count + lost_count,
                "next_id " + std::to_string(next_id) + " is not the particles made (" +
                    std::to_string(n) + " present + " + std::to_string(discharged_count) +
                    " discharged + " + std::to_string(lost_count) + " lost)");
  check_particles(check, particles, next_id, int(scene.materials.size()),
                  int(family_of_shape.size()), int(sources.size()), int(tag_names.size()));
  // The cell grid of the pair list and the wall bins are sized from largest_radius: below a
  // particle's radius they would miss pairs and walls within reach, with no error.
  const auto radius = host_copy(particles.radius);
  double largest = 0, smallest = std::numeric_limits<double>::infinity();
  for (long i = 0; i < n; ++i) {
    largest = std::max(largest, radius(i));
    smallest = std::min(smallest, radius(i));
  }
  const auto text = [](double x) {
    std::ostringstream out;
    out << x;
    return out.str();
  };
  check.require(largest_radius >= largest, "largest_radius " + text(largest_radius) +
                                               " is below the largest particle radius " +
                                               text(largest));
  check.require(n == 0 || smallest_radius <= smallest,
                "smallest_radius " + text(smallest_radius) +
                    " is above the smallest particle radius " + text(smallest));
}

void Engine::State::check_restored_lists(const std::string& path) const {
  const RestoreCheck check(path);

  // The lists index the particle order of their build (ids_at_build), which is the present one
  // unless a rebuild is due.
  const long built = long(ids_at_build.extent(0));
  check.indices("ids_at_build", ids_at_build, 0, next_id);
  check.unique("ids_at_build", ids_at_build);
  if (!needs_rebuild)
    check.same("ids_at_build differs from particles/id with no rebuild due", ids_at_build,
               particles.id);
  const bool built_once = pairs.row_start.extent(0) != 0 || wall_contacts.row_start.extent(0) != 0;
  check.require(built_once || needs_rebuild, "no lists and no rebuild due");
  if (!built_once) {
    check.require(pairs.pair_count == 0 && wall_contacts.entry_count == 0,
                  "list entries without lists");
    return;
  }
  const ListContext context{particles,
                            shape_families,
                            families_present,
                            rolling,
                            needs_narrow_phase_state(),
                            needs_rebuild,
                            built,
                            walls.elements.count,
                            surface_travel};
  check_pairs(check, pairs, context);
  check_wall_contacts(check, wall_contacts, context);
}

} // namespace kdem
