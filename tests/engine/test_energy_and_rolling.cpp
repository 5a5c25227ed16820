// Conservation and history tests: energy of an elastic frictionless gas, rolling resistance
// stopping distance, angular momentum of a frictional collision, and contact history across
// candidate-list rebuilds.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <random>

#include "scene_builders.hpp"

namespace kdem::testing {
namespace {

double sphere_mass(const MaterialConfig& m, double radius) {
  return m.density * 4.0 / 3.0 * M_PI * radius * radius * radius;
}

// Positions by stable particle id.
std::map<std::int64_t, Vec3d> positions_by_id(const ParticleSnapshot& s) {
  std::map<std::int64_t, Vec3d> out;
  for (std::size_t i = 0; i < s.size(); ++i)
    out[s.id[i]] = {s.position[3 * i], s.position[3 * i + 1], s.position[3 * i + 2]};
  return out;
}

WallConfig box_wall(const std::string& material, Vec3d lo, Vec3d hi) {
  WallConfig w;
  w.kind = WallConfig::Kind::Box;
  w.name = "box";
  w.material = material;
  w.min = lo;
  w.max = hi;
  return w;
}

// --- (a) elastic frictionless gas -----------------------------------------------------------

struct GasRun {
  double worst_relative_error = 0; // |E_kin / E_0 - 1| at contact-free samples
  int contact_free_samples = 0;
  int samples_with_contacts = 0;
  double last_contact_free_time = 0;
  double duration = 0;
  double seconds = 0;
};

// 1000 spheres (R = 1 mm, 10 x 10 x 10 lattice with jitter) in a closed box of solid fraction
// 1 %, velocity components normal with sigma = 1 m/s, no gravity, e = 1, mu = 0, mu_r = 0.
// Hertz contact time at the largest relative speeds (~6 m/s) t_c ~ 16 us; dt = t_c / 40.
// The total kinetic energy is sampled every 25 steps, and compared with the initial one at
// the samples where no pair and no wall contact is open (then the elastic energy
// 2/5 k d^2.5 of the contacts, which the engine does not report, is zero).
GasRun run_elastic_gas(std::int64_t steps) {
  const MaterialConfig m = material("elastic", 1000, 1e9, 0.3, 1.0, 0.0, 0.0);
  const double radius = 1e-3;
  const int per_side = 10;
  const double volume =
      per_side * per_side * per_side * 4.0 / 3.0 * M_PI * std::pow(radius, 3) / 0.01;
  const double side = std::cbrt(volume), spacing = side / per_side;
  SceneConfig scene = empty_scene(4e-7, {m});
  scene.domain_min = {0, 0, 0};
  scene.domain_max = {side, side, side};
  scene.walls.push_back(box_wall("elastic", {0, 0, 0}, {side, side, side}));
  Engine engine(scene);
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> jitter(-0.25 * spacing, 0.25 * spacing);
  std::normal_distribution<double> speed(0.0, 1.0);
  std::vector<ParticleInit> particles;
  for (int i = 0; i < per_side; ++i)
    for (int j = 0; j < per_side; ++j)
      for (int k = 0; k < per_side; ++k) {
        const Vec3d x{(i + 0.5) * spacing + jitter(rng), (j + 0.5) * spacing + jitter(rng),
                      (k + 0.5) * spacing + jitter(rng)};
        particles.push_back(sphere(x, radius, {speed(rng), speed(rng), speed(rng)}));
      }
  engine.add_particles(particles);
  const Diagnostics start = engine.diagnostics();
  EXPECT_EQ(start.pair_contacts + start.wall_contacts, 0);
  const double initial = start.translational_energy + start.rotational_energy;
  GasRun run;
  const auto t0 = std::chrono::steady_clock::now();
  const int interval = 25;
  for (std::int64_t done = 0; done < steps; done += interval) {
    engine.advance(interval);
    const Diagnostics d = engine.diagnostics();
    if (d.pair_contacts + d.wall_contacts > 0) {
      ++run.samples_with_contacts;
      continue;
    }
    ++run.contact_free_samples;
    run.last_contact_free_time = d.time;
    const double energy = d.translational_energy + d.rotational_energy;
    run.worst_relative_error = std::max(run.worst_relative_error, std::abs(energy / initial - 1));
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.duration = engine.time();
  return run;
}

void check_gas(const GasRun& run) {
  EXPECT_LT(run.worst_relative_error, 1e-4);
  // The gas must be collisional (else the test proves nothing) and contact-free instants must
  // occur up to the end of the run.
  EXPECT_GT(run.samples_with_contacts, run.contact_free_samples / 10);
  EXPECT_GT(run.contact_free_samples, 20);
  EXPECT_GT(run.last_contact_free_time, 0.9 * run.duration);
}

TEST(EnergyConservation, ElasticFrictionlessGasTenThousandSteps) {
  check_gas(run_elastic_gas(10000));
}

TEST(LongEnergyConservation, ElasticFrictionlessGasHundredThousandSteps) {
  check_gas(run_elastic_gas(100000));
}

// --- (b) rolling resistance ----------------------------------------------------------------

// Equilibrium overlap of a sphere pressed by `load` on a plane (Hertz: load = 4/3 E* sqrt(R)
// d^1.5).
double resting_overlap(double load, double effective_youngs, double radius) {
  return std::pow(load / (4.0 / 3.0 * effective_youngs * std::sqrt(radius)), 2.0 / 3.0);
}

// A sphere (R = 5 mm, 2500 kg/m^3, E = 1 GPa) rolling without slip on the plane z = 0 under
// gravity, mu = 0.5, mu_r = 0.1, v0 = 0.1 m/s along `direction`, omega0 = v0 / R. It starts
// at its resting overlap (the state it settles to), so that no normal oscillation is excited.
// With the EPSD2 torque at its plastic limit, M = mu_r R m g, opposing the rolling:
//   m a = F (friction),  I alpha = -R F - mu_r R m g,  a = R alpha (no slip)
//   => a = -mu_r g / (1 + I / (m R^2)) = -mu_r g / 1.4,  stopping distance 0.7 v0^2 / (mu_r g).
// (The friction needed, mu_r m g / 1.4, is far below mu m g, so the sphere does not slip.)
TEST(RollingResistance, SphereStopsAtTheModelsDistance) {
  const double radius = 5e-3, g = 9.81, mu = 0.5, mu_r = 0.1, v0 = 0.1;
  const MaterialConfig m = material("ball", 2500, 1e9, 0.3, 0.5, mu, mu_r);
  const double mass = sphere_mass(m, radius);
  const double overlap = resting_overlap(mass * g, effective_youngs(m, m), radius);
  for (const Vec3d direction : {Vec3d{1, 0, 0}, Vec3d{-0.6, 0.8, 0}}) {
    SceneConfig scene = empty_scene(1e-5, {m});
    scene.gravity = {0, 0, -g};
    scene.walls.push_back(plane_wall("ball", {0, 0, 0}, {0, 0, 1}));
    Engine engine(scene);
    ParticleInit p =
        sphere({0, 0, radius - overlap}, radius, {v0 * direction[0], v0 * direction[1], 0});
    // Rolling: v = omega x (R n) with n = +z, so omega = (n x v) / R.
    p.angular_velocity = {-v0 * direction[1] / radius, v0 * direction[0] / radius, 0};
    engine.add_particles({p});
    const double deceleration = mu_r * g / 1.4;
    const double stop_time = v0 / deceleration;
    const double expected = 0.7 * v0 * v0 / (mu_r * g);
    double farthest = 0, worst_slip = 0, half_time = -1, speed_at_half = 0;
    const auto total_steps = std::int64_t(1.3 * stop_time / engine.time_step());
    for (std::int64_t k = 0; k < total_steps; k += 10) {
      engine.advance(10);
      const ParticleSnapshot s = engine.snapshot();
      const double along = s.position[0] * direction[0] + s.position[1] * direction[1];
      const double v = s.velocity[0] * direction[0] + s.velocity[1] * direction[1];
      const double w = -s.angular_velocity[0] * direction[1] + s.angular_velocity[1] * direction[0];
      farthest = std::max(farthest, along);
      if (engine.time() < 0.9 * stop_time)
        worst_slip = std::max(worst_slip, std::abs(v - radius * w));
      if (half_time < 0 && engine.time() >= 0.5 * stop_time)
        half_time = engine.time(), speed_at_half = v;
    }
    // Stopping distance, 1e-3 relative (observed 3e-5). Model effects not in the formula are
    // smaller: the rolling spring's build-up to its limit (rotation mu_r R F_n / k_r, i.e.
    // 0.3 d / mu_r = 1e-4 of the distance), the lever arm R - d/2 (d / 2R = 2.5e-5), and
    // sampling the farthest point every 10 steps near v = 0 (< 1e-8).
    EXPECT_NEAR(farthest, expected, 1e-3 * expected);
    // Constant deceleration: the speed half-way, 1e-3 relative for the same reasons.
    EXPECT_NEAR(speed_at_half, v0 - deceleration * half_time, 1e-3 * v0);
    // Rolling without slip: the contact point moves only by the tangential spring's small
    // elastic oscillation (observed 1.4e-3 v0); a sliding sphere would show ~v0.
    EXPECT_LT(worst_slip, 0.01 * v0);
  }
}

// --- (c) history across list rebuilds -------------------------------------------------------

// 75 spheres (R = 2 mm) on a 5 x 5 x 3 lattice of spacing 3.98 mm (every neighbour overlapping
// by 20 um) in a 2 cm box, with random velocities of up to 5 cm/s, under gravity, with
// friction and rolling resistance: from the first step on, dozens of pair and wall contacts
// carry tangential springs and rolling torques, some sticking and some sliding, while the pack
// collapses. They are added in reverse lattice order, so the first sort permutes them.
struct PackRun {
  std::map<std::int64_t, Vec3d> positions;
  Diagnostics end;
};

PackRun collapse_pack(bool rebuild_every_step, std::int64_t steps) {
  const MaterialConfig m = material("grain", 2500, 1e8, 0.3, 0.5, 0.5, 0.05);
  SceneConfig scene = empty_scene(2e-6, {m});
  scene.gravity = {0, 0, -9.81};
  scene.domain_min = {0, 0, 0};
  scene.domain_max = {0.02, 0.02, 0.02};
  scene.walls.push_back(box_wall("grain", {0, 0, 0}, {0.02, 0.02, 0.02}));
  Engine engine(scene);
  engine.set_rebuild_every_step(rebuild_every_step);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> speed(-0.05, 0.05);
  std::vector<ParticleInit> particles;
  const double radius = 2e-3, spacing = 3.98e-3;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i)
        particles.push_back(sphere(
            {0.5 * spacing + spacing * i, 0.5 * spacing + spacing * j, 0.5 * spacing + spacing * k},
            radius, {speed(rng), speed(rng), speed(rng)}));
  std::reverse(particles.begin(), particles.end());
  engine.add_particles(particles);
  engine.advance(steps);
  return {positions_by_id(engine.snapshot()), engine.diagnostics()};
}

// Rebuilding the lists every step re-sorts the particles and moves every contact's history to
// a fresh list by stable ids each step; the default rebuilds only when a particle has moved
// half the skin. Both must integrate the same contacts with the same history. The results are
// bitwise equal until a particle changes cell between two default rebuilds: from then on the
// two runs hold the particles in different orders, so a pair may be evaluated from the other
// side (i and j swapped) and the gather adds the same forces in another order, which changes
// the last bits. Those round-off differences (first seen here after ~700 steps, at 4e-19 m)
// grow as the pack's dynamics amplify them (about x10 per 500 steps here): after 4000 steps
// they are ~2e-15 m, so 1e-12 of the box size (2e-14 m) is the tolerance. A lost or misplaced
// history changes the tangential forces by ~mu F_n and the positions by ~1e-5 m in that time.
TEST(ContactHistory, SameResultWhetherListsAreRebuiltEveryStepOrRarely) {
  const std::int64_t steps = 4000;
  const PackRun rare = collapse_pack(false, steps);
  const PackRun every = collapse_pack(true, steps);
  double worst = 0;
  for (const auto& [id, x] : rare.positions) {
    const Vec3d& y = every.positions.at(id);
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(x[c] - y[c]));
  }
  EXPECT_LE(worst, 1e-12 * 0.02);
  // The comparison is meaningful: many rebuilds on one side, few on the other, and contacts
  // still open at the end.
  EXPECT_GE(every.end.list_builds, steps);
  EXPECT_LE(rare.end.list_builds, steps / 100);
  EXPECT_GE(rare.end.pair_contacts, 10);
  EXPECT_EQ(rare.end.pair_contacts, every.end.pair_contacts);
  EXPECT_EQ(rare.end.wall_contacts, every.end.wall_contacts);
}

// --- (d) static friction held across rebuilds -------------------------------------------------

// Four spheres (R = 5 mm, E = 100 MPa) at rest on a plane inclined by 8 degrees, with mu = 0.6
// and mu_r = 0.4 (> tan 8 deg = 0.14: the tangential spring and the rolling torque can hold
// them), the lists rebuilt every step for 20000 steps (0.4 s). Each sphere starts at its
// resting overlap with unloaded springs, so it first moves down the slope until the tangential
// spring (F_t = m g sin(theta) = k_t xi) and the rolling torque (M_r = F_t R = k_r phi) carry the
// load: a static displacement of xi + R phi, overshooting by at most as much again (a spring
// released from its unloaded state). The bound is 3 (xi + R phi). If history were lost at a
// rebuild, the springs would restart from zero every step and the spheres would roll away
// (a = g sin(theta) / 1.4: 1.5 cm in 0.2 s).
TEST(ContactHistory, StaticFrictionOnAnInclineSurvivesRebuildsEveryStep) {
  const double radius = 5e-3, g = 9.81, slope = 8 * M_PI / 180, mu = 0.6, mu_r = 0.4;
  const MaterialConfig m = material("grain", 2500, 1e8, 0.3, 0.5, mu, mu_r);
  const double mass = sphere_mass(m, radius);
  const double youngs = effective_youngs(m, m);
  const double shear = 1.0 / (4 * (2 - m.poisson_ratio) * (1 + m.poisson_ratio) / m.youngs_modulus);
  const double overlap = resting_overlap(mass * g * std::cos(slope), youngs, radius);
  const double contact_radius = std::sqrt(radius * overlap);
  const double tangential_stiffness = 8 * shear * contact_radius;
  const double rolling_stiffness =
      2.25 * 2 * youngs * contact_radius * mu_r * mu_r * radius * radius;
  const double load = mass * g * std::sin(slope);
  const double static_shift =
      load / tangential_stiffness + radius * load * radius / rolling_stiffness;
  SceneConfig scene = empty_scene(2e-5, {m});
  scene.gravity = {0, 0, -g};
  scene.domain_min = {-0.06, -0.04, -0.02}; // a small domain keeps the per-step sort cheap
  scene.domain_max = {0.06, 0.04, 0.02};
  // The plane through the origin rises along +x: normal (-sin, 0, cos); down-slope is -x.
  const Vec3d normal{-std::sin(slope), 0, std::cos(slope)};
  scene.walls.push_back(plane_wall("grain", {0, 0, 0}, normal));
  Engine engine(scene);
  engine.set_rebuild_every_step(true);
  std::vector<ParticleInit> particles;
  const Vec3d up_slope{std::cos(slope), 0, std::sin(slope)};
  for (int k = 0; k < 4; ++k) {
    const double along = 0.045 - 0.03 * k, across = 0.02 * k - 0.03; // apart, in different cells
    Vec3d x;
    for (int c = 0; c < 3; ++c)
      x[c] = along * up_slope[c] + (radius - overlap) * normal[c];
    x[1] = across;
    particles.push_back(sphere(x, radius));
  }
  engine.add_particles(particles);
  const auto start = positions_by_id(engine.snapshot());
  auto largest_shift = [&](const std::map<std::int64_t, Vec3d>& from) {
    double worst = 0;
    for (const auto& [id, x] : positions_by_id(engine.snapshot())) {
      const Vec3d& x0 = from.at(id);
      worst = std::max(worst, std::sqrt(std::pow(x[0] - x0[0], 2) + std::pow(x[1] - x0[1], 2) +
                                        std::pow(x[2] - x0[2], 2)));
    }
    return worst;
  };
  double worst = 0;
  std::map<std::int64_t, Vec3d> half;
  for (int block = 0; block < 20; ++block) {
    engine.advance(1000);
    worst = std::max(worst, largest_shift(start));
    if (block == 9)
      half = positions_by_id(engine.snapshot());
  }
  EXPECT_LT(worst, 3 * static_shift);
  // No creep in the second half: the oscillation about the static position is damped through
  // the tangential dashpot (observed late movement: 3e-3 of the static shift).
  EXPECT_LT(largest_shift(half), 0.5 * static_shift);
  EXPECT_GE(engine.diagnostics().list_builds, 20000);
  EXPECT_EQ(engine.diagnostics().wall_contacts, 4);
}

// --- (e) angular momentum of a frictional, rolling collision ------------------------------

// Two spheres of unequal size and spin meet off centre with friction and rolling resistance:
// every step kicks the total angular momentum about the origin by h (sum of x x F + T), which a
// pair's forces and its torques on i and on j make zero, and a drift changes sum m x x v by
// m v x v dt = 0. So the total stays what it was to rounding: a few ulps a step of its largest
// terms, m |x| |v| ~ 6e-8 kg m^2/s, a random walk of ~1e-14 of it over 10,000 steps (5e-14
// seen); the bound 1e-12 leaves a factor of 20, while a torque on j off by a lever arm of the
// overlap (~1e-6 m) would move it by ~1e-4. The spins change by tens of percent.
TEST(AngularMomentum, FrictionalRollingSpheresKeepItToRounding) {
  SceneConfig scene = empty_scene(2e-7, {material("glass", 2500, 1e8, 0.3, 0.6, 0.5, 0.3)});
  Engine engine(scene);
  ParticleInit a = sphere({-1.2e-3, 0.5e-3, 0.1e-3}, 1e-3, {1.0, 0, 0});
  a.angular_velocity = {0, 300, -200};
  ParticleInit b = sphere({1.5e-3, -0.4e-3, 0}, 1.4e-3, {-0.5, 0.1, 0});
  b.angular_velocity = {150, 0, 400};
  engine.add_particles({a, b});
  auto total = [&] { // the snapshot's rows follow the engine's order, which its sorts change
    const ParticleSnapshot s = engine.snapshot();
    Vec3 l{};
    for (int i = 0; i < 2; ++i) {
      const double mass = sphere_mass(scene.materials[0], s.radius[i]);
      l = l + mass * cross(row3(s.position, i), row3(s.velocity, i)) +
          (0.4 * mass * s.radius[i] * s.radius[i]) * row3(s.angular_velocity, i);
    }
    return l;
  };
  const Vec3 before = total();
  for (int k = 0; k < 10000; ++k)
    engine.step();
  const Vec3 after = total();
  const double scale = sphere_mass(scene.materials[0], 1.4e-3) * 2e-3 * 1.0; // m |x| |v|
  EXPECT_LT(norm(after - before), 1e-12 * scale);
  RecordProperty("angular_momentum_change_over_scale",
                 std::to_string(norm(after - before) / scale));
  // The contact did act: the smaller sphere's spin about y changed.
  const ParticleSnapshot s = engine.snapshot();
  const int small = s.radius[0] < s.radius[1] ? 0 : 1;
  EXPECT_GT(std::abs(s.angular_velocity[3 * small + 1] - 300), 0.1 * 300);
}

} // namespace
} // namespace kdem::testing
