// Several contact points per pair: a test family of rigid dumbbells (two spheres on a rod) has up
// to four contacts per pair, one per pair of lobes. One dumbbell slides over another, so that
// contacts appear, move and vanish; the pair loop's forces must equal those of independent
// sphere contacts with one history per lobe pair (the brute-force reference), with history
// carried by feature, nothing counted twice, and across a list rebuild that flips the pair.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "contact_test_support.hpp"
#include "kernels/families/pair_loop.hpp"
#include "src/host_copy.hpp"

namespace kdem {

// Lobes of radius lobe_radius at body-frame x = -lobe_offset (feature 0) and +lobe_offset (1).
struct DumbbellFamily {
  static constexpr const char* name = "test_dumbbell";
  static constexpr int contact_points = 2;
  struct Table {};
};

constexpr double lobe_radius = 1e-3;   // m
constexpr double lobe_offset = 2e-3;   // m
constexpr double lobe_height = 1.9e-3; // m, the upper dumbbell's centre above the lower one's

KOKKOS_INLINE_FUNCTION Vec3 lobe_centre(const ParticleViews& p, int i, int lobe) {
  const Vec3 along = rotate(load_quat(p.orientation, i), Vec3{1, 0, 0});
  return load3(p.position, i) + ((lobe == 0 ? -1.0 : 1.0) * lobe_offset) * along;
}

template <> struct NarrowPhase<DumbbellFamily, DumbbellFamily> : EveryRowOfTheType {
  static constexpr const char* label = "kdem::test_dumbbell_pairs";
  static constexpr bool tallied = false;
  static constexpr int max_contacts = 4;
  int team_size = 0;
  ParticleViews p;

  explicit NarrowPhase(const ContactContext& c) : p(c.particles) {}

  KOKKOS_INLINE_FUNCTION PairOutcome operator()(const PairRef& r, PairContacts<4>& found,
                                                NarrowPhaseTally&) const {
    for (int lobe_a = 0; lobe_a < 2; ++lobe_a)
      for (int lobe_b = 0; lobe_b < 2; ++lobe_b) {
        const ContactGeometry g = sphere_sphere(lobe_centre(p, r.a, lobe_a), lobe_radius,
                                                lobe_centre(p, r.b, lobe_b), lobe_radius);
        if (!g.touching)
          continue;
        PairContact& contact = found.add();
        contact.geometry = g;
        contact.effective_radius = 0.5 * lobe_radius;
        contact.feature_a = lobe_a;
        contact.feature_b = lobe_b;
      }
    return found.count > 0 ? PairOutcome::touching : PairOutcome::apart;
  }
};

namespace {

// A fixed number of contact slots per candidate (a functor: nvcc takes no device lambda in a
// test body).
struct SlotsEach {
  int slots = 1;
  KOKKOS_INLINE_FUNCTION int operator()(int) const { return slots; }
};

// Independent sphere contacts between the lobes, with a history per lobe pair (lower, upper):
// the forces on the lower dumbbell.
struct LobeReference {
  ContactHistory history[2][2] = {};
  Vec3 step(const Vec3 lower_lobes[2], const Vec3 upper_lobes[2], Vec3 lower_v, Vec3 upper_v,
            double effective_mass, double dt, int& touching) {
    Vec3 total;
    touching = 0;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        const ContactGeometry g =
            sphere_sphere(lower_lobes[a], lobe_radius, upper_lobes[b], lobe_radius);
        if (!g.touching) {
          history[a][b] = ContactHistory{};
          continue;
        }
        ContactInput in;
        in.geometry = g;
        in.relative_velocity = lower_v - upper_v;
        in.effective_radius = 0.5 * lobe_radius;
        in.effective_mass = effective_mass;
        total += hertz_mindlin<false>(testing::glass_pair(), in, dt, history[a][b]).force_on_i;
        ++touching;
      }
    return total;
  }
};

template <class View>
View from_host(const std::string& label, const std::vector<typename View::non_const_value_type>& v,
               int columns) {
  return view_from_host<View>(label, v, columns);
}

// Two parallel dumbbells, the upper one sliding along -x at `speed`; stored as the pair
// (first, second) of rows 0 and 1, where row `lower_row` is the lower dumbbell.
struct SlidingDumbbells {
  ContactContext c;
  PairList& list = c.pairs;
  int lower_row = 0;
  double speed = 0.1;    // m/s
  double dt = 1e-4;      // s
  double shift = 4.7e-3; // m, x of the upper dumbbell's centre

  explicit SlidingDumbbells(int lower) : lower_row(lower) {
    c.particles.allocate(2);
    c.particles.mass = from_host<ScalarView>("mass", {1e-5, 1e-5}, 1);
    c.particles.material = from_host<IndexView>("material", {0, 0}, 1);
    c.particles.orientation = from_host<QuatView>("orientation", {1, 0, 0, 0, 1, 0, 0, 0}, 4);
    c.coefficients = CoefficientTable("coefficients", 1, 1);
    auto table = Kokkos::create_mirror_view(c.coefficients);
    table(0, 0) = testing::glass_pair();
    Kokkos::deep_copy(c.coefficients, table);
    c.dt = dt;
    list = one_pair_list(0, 1);
  }

  static PairList one_pair_list(int i, int j) {
    PairList l;
    l.pair_count = 1;
    l.row_start = from_host<IndexView>(
        "row_start", i == 0 ? std::vector<int>{0, 1, 1} : std::vector<int>{0, 0, 1}, 1);
    l.pair_i = from_host<IndexView>("pair_i", {i}, 1);
    l.pair_j = from_host<IndexView>("pair_j", {j}, 1);
    l.partner_id = from_host<IdView>("partner_id", {std::int64_t(j)}, 1);
    l.reverse_start = from_host<IndexView>(
        "reverse_start", j == 1 ? std::vector<int>{0, 0, 1} : std::vector<int>{0, 1, 1}, 1);
    l.reverse_pair = from_host<IndexView>("reverse_pair", {0}, 1);
    assign_contact_slots(l, SlotsEach{4});
    allocate_pair_contacts(l, false, false);
    return l;
  }

  Vec3 upper_velocity() const { return {-speed, 0, 0}; }

  void place() {
    std::vector<double> x(6, 0.0), v(6, 0.0);
    const int upper_row = 1 - lower_row;
    x[3 * upper_row] = shift;
    x[3 * upper_row + 2] = lobe_height;
    v[3 * upper_row] = -speed;
    c.particles.position = from_host<Vec3View>("position", x, 3);
    c.particles.velocity = from_host<Vec3View>("velocity", v, 3);
    c.particles.id = from_host<IdView>("id", {0, 1}, 1);
  }

  // One step of the pair loop; the force on the lower dumbbell (whichever body of the pair).
  Vec3 step() {
    place();
    PairTypeRows rows;
    rows.rows = RowSet{1, true, {}};
    compute_pair_type<DumbbellFamily, DumbbellFamily, HertzMindlin<false>>(c, rows);
    const std::vector<double> f = flatten_to_host(list.force_on_i, 1);
    const Vec3 on_i{f[0], f[1], f[2]};
    const int i = flatten_to_host(list.pair_i, 1)[0];
    return i == lower_row ? on_i : -on_i;
  }

  int touching_slots() const {
    int n = 0;
    for (double overlap : flatten_to_host(list.overlap, list.slot_count))
      n += overlap > 0 ? 1 : 0;
    return n;
  }

  void reference_lobes(Vec3 lower[2], Vec3 upper[2]) const {
    for (int lobe = 0; lobe < 2; ++lobe) {
      const double x = (lobe == 0 ? -1.0 : 1.0) * lobe_offset;
      lower[lobe] = Vec3{x, 0, 0};
      upper[lobe] = Vec3{shift + x, 0, lobe_height};
    }
  }
};

// Forces agree to rounding: both sides evaluate the same formulas, possibly with the pair's
// bodies in the other order (which negates the relative velocity and the normal).
void expect_same_force(Vec3 engine, Vec3 reference) {
  const double scale = 1e-12 * (norm(reference) + 1e-9);
  EXPECT_NEAR(engine.x, reference.x, scale);
  EXPECT_NEAR(engine.y, reference.y, scale);
  EXPECT_NEAR(engine.z, reference.z, scale);
}

// Runs `steps` steps, checking every step against the reference; counts the steps with 0, 1
// and 2 contacts.
void slide(SlidingDumbbells& s, LobeReference& reference, int steps, int (&seen)[3]) {
  const double effective_mass = 0.5e-5;
  for (int n = 0; n < steps; ++n) {
    Vec3 lower[2], upper[2];
    s.reference_lobes(lower, upper);
    int touching = 0;
    const Vec3 expected =
        reference.step(lower, upper, Vec3{}, s.upper_velocity(), effective_mass, s.dt, touching);
    const Vec3 found = s.step();
    expect_same_force(found, expected);
    EXPECT_EQ(s.touching_slots(), touching) << "step " << n;
    seen[touching < 3 ? touching : 2]++;
    s.shift -= s.speed * s.dt;
  }
}

} // namespace

TEST(ContactPoints, ContactsAppearMoveAndVanishWithTheirOwnHistory) {
  SlidingDumbbells s(0);
  LobeReference reference;
  int seen[3] = {0, 0, 0};
  // From a shift of 4.7 mm down to 0: lobe pair (1, 0) touches from 4.62 to 3.38 mm, then the
  // lobe pairs (0, 0) and (1, 1) from 0.62 mm on.
  slide(s, reference, 470, seen);
  EXPECT_GT(seen[0], 0);
  EXPECT_GT(seen[1], 0);
  EXPECT_GT(seen[2], 0);
  // The sliding contacts have built up a tangential spring: the history is carried.
  const std::vector<double> spring = flatten_to_host(s.list.tangential_spring, s.list.slot_count);
  double largest = 0;
  for (double component : spring)
    largest = std::max(largest, std::abs(component));
  EXPECT_GT(largest, 0.1 * s.speed * s.dt);
}

TEST(ContactPoints, HistoryFollowsItsFeaturesAcrossARebuildThatFlipsThePair) {
  SlidingDumbbells s(0);
  LobeReference reference;
  int seen[3] = {0, 0, 0};
  // Lobe 1 of the lower dumbbell under lobe 0 of the upper one: one contact whose features
  // differ, so that a flip of the pair must swap them.
  s.shift = 4.3e-3;
  slide(s, reference, 20, seen);
  ASSERT_EQ(s.touching_slots(), 1);
  // A rebuild stores the pair as (1, 0): row 1 is now the lower dumbbell's partner list owner.
  const PairList old = s.list;
  PairList fresh = SlidingDumbbells::one_pair_list(1, 0);
  const IndexView old_rows = rows_by_id(s.c.particles.id, 2, 2);
  transfer_pair_history(fresh, old, old_rows, s.c.particles.id);
  const std::vector<int> old_i = flatten_to_host(old.feature_i, 4);
  const std::vector<int> old_j = flatten_to_host(old.feature_j, 4);
  const std::vector<int> new_i = flatten_to_host(fresh.feature_i, 4);
  const std::vector<int> new_j = flatten_to_host(fresh.feature_j, 4);
  for (int slot = 0; slot < 4; ++slot) {
    EXPECT_EQ(new_i[slot], old_j[slot]);
    EXPECT_EQ(new_j[slot], old_i[slot]);
  }
  s.list = fresh;
  // On past the end of that contact (at 3.38 mm); the reference keeps its histories, so the
  // forces agree only if the history moved with its features.
  slide(s, reference, 100, seen);
  EXPECT_EQ(s.touching_slots(), 0);
}

// A dumbbell against the plane z = 0: one contact per lobe below the plane, keyed by the lobe.
struct DumbbellOnPlane {
  static constexpr int max_contacts = 2;
  ParticleViews p;

  KOKKOS_INLINE_FUNCTION void operator()(int i, int, const WallPose&,
                                         WallContacts<2>& found) const {
    for (int lobe = 0; lobe < 2; ++lobe) {
      const Vec3 centre = lobe_centre(p, i, lobe);
      const ContactGeometry g = sphere_on_surface(centre, lobe_radius, centre.z, Vec3{0, 0, 1});
      if (!g.touching)
        continue;
      WallContactGeometry& contact = found.add();
      contact.geometry = g;
      contact.effective_radius = lobe_radius;
      contact.feature = lobe;
    }
  }
};

// A dumbbell tilted by 0.05 rad about y (lobe 1 lower), sliding along x while it descends onto a
// plane and lifts off again: lobe 1 touches first, then lobe 0, then they let go in reverse. The
// wall loop's force must equal independent sphere-plane contacts with one history per lobe.
TEST(ContactPoints, ParticleWallContactsAppearAndVanishPerFeature) {
  const double tilt = 0.05, speed = 0.1, dt = 1e-4, mass = 1e-5;
  ParticleViews p;
  p.allocate(1);
  p.mass = from_host<ScalarView>("mass", {mass}, 1);
  p.material = from_host<IndexView>("material", {0}, 1);
  p.orientation =
      from_host<QuatView>("orientation", {std::cos(0.5 * tilt), 0, std::sin(0.5 * tilt), 0}, 4);
  WallSet walls;
  walls.wall_count = 1;
  walls.elements.count = 1;
  walls.elements.wall = from_host<IndexView>("wall", {0}, 1);
  walls.elements.kind = from_host<IndexView>("kind", {plane_element}, 1);
  walls.pose = DeviceView<WallPose*>("pose", 1); // at rest, identity, active, material 0
  WallContactList list;
  list.entry_count = 1;
  list.row_start = from_host<IndexView>("row_start", {0, 1}, 1);
  list.element = from_host<IndexView>("element", {0}, 1);
  list.element_key = from_host<IdView>("element_key", {0}, 1);
  assign_wall_contact_slots(list, 1, SlotsEach{2});
  allocate_wall_contacts(list, walls.elements, false);
  CoefficientTable table("coefficients", 1, 1);
  auto host_table = Kokkos::create_mirror_view(table);
  host_table(0, 0) = testing::glass_pair();
  Kokkos::deep_copy(table, host_table);

  ContactHistory reference[2] = {};
  int seen[3] = {0, 0, 0};
  double x = 0, z = 1.15e-3;
  for (int n = 0; n < 60; ++n) {
    const double vz = n < 30 ? -speed : speed;
    p.position = from_host<Vec3View>("position", {x, 0, z}, 3);
    p.velocity = from_host<Vec3View>("velocity", {speed, 0, vz}, 3);
    compute_wall_contacts<HertzMindlin<false>>("kdem::test_dumbbell_wall", p, walls, list, table,
                                               dt, 1, AllRows{}, DumbbellOnPlane{p});
    Vec3 expected;
    int touching = 0;
    const Vec3 along{std::cos(tilt), 0, -std::sin(tilt)};
    for (int lobe = 0; lobe < 2; ++lobe) {
      const Vec3 centre = Vec3{x, 0, z} + ((lobe == 0 ? -1.0 : 1.0) * lobe_offset) * along;
      const ContactGeometry g = sphere_on_surface(centre, lobe_radius, centre.z, Vec3{0, 0, 1});
      if (!g.touching) {
        reference[lobe] = ContactHistory{};
        continue;
      }
      ContactInput in;
      in.geometry = g;
      in.relative_velocity = Vec3{speed, 0, vz};
      in.effective_radius = lobe_radius;
      in.effective_mass = mass;
      expected += hertz_mindlin<false>(testing::glass_pair(), in, dt, reference[lobe]).force_on_i;
      ++touching;
    }
    const std::vector<double> f = flatten_to_host(list.force_on_i, 1);
    const Vec3 found{f[0], f[1], f[2]};
    // The lobe centres differ from the reference's by the rotation's rounding (1e-19 m).
    const double tolerance = 1e-9 * (norm(expected) + 1e-9);
    EXPECT_NEAR(found.x, expected.x, tolerance) << "step " << n;
    EXPECT_NEAR(found.z, expected.z, tolerance) << "step " << n;
    int slots_touching = 0;
    for (double overlap : flatten_to_host(list.overlap, list.slot_count))
      slots_touching += overlap > 0 ? 1 : 0;
    EXPECT_EQ(slots_touching, touching) << "step " << n;
    ++seen[touching];
    x += speed * dt;
    z += vz * dt;
  }
  EXPECT_GT(seen[0], 0);
  EXPECT_GT(seen[1], 0);
  EXPECT_GT(seen[2], 0);
}

TEST(ContactPoints, PairsOfOneContactKeepOneSlotEach) {
  PairList l;
  l.pair_count = 3;
  allocate_pair_contacts(l, false, false);
  EXPECT_TRUE(l.one_slot_per_pair());
  EXPECT_EQ(l.slot_count, 3);
  EXPECT_EQ(l.feature_i.extent(0), 0u);
}

} // namespace kdem
