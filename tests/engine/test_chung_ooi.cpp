// Benchmarks of Chung & Ooi, "Benchmark tests for verifying discrete element modelling codes
// at particle impact level", Granular Matter 13 (2011) 643-656, tests 1 to 5 of the paper:
//
//   ChungOoiTest1  paper test 1: elastic normal impact of two identical spheres
//   ChungOoiTest2  paper tests 2 and 3: normal impact of a sphere on a rigid plane, elastic
//                  (Hertz quantities) and with coefficients of restitution 0.2 ... 1.0
//   ChungOoiTest3  paper test 4: oblique impact at a constant resultant speed of 3.9 m/s and
//                  incidence angles 0 ... 89 degrees
//   ChungOoiTest4  paper test 5: oblique impact at a constant normal speed and tangential speeds
//                  from 0.1 to 70 m/s
//
// Parameters. The materials, radii and speeds below are the paper's as reproduced by public
// re-implementations of the benchmark (the examples of Yade and PySPH); where the paper's exact
// value is not known to us this is said next to the value. The paper's "rigid plane" is a plane
// wall 1000 times stiffer than the sphere (as in the Yade examples); every Hertz reference below
// uses the effective modulus of the actual pair, so the finite stiffness of the plane is not an
// error source.
//
// References used for the assertions.
//  - Normal impacts: Hertz's elastic impact (scene_builders.hpp, hertz_impact) and the requested
//    coefficient of restitution.
//  - Oblique impacts, gross sliding: with a sliding contact throughout, the friction impulse is
//    mu times the normal impulse J_n = m (1 + e) v_n (rigid-body Coulomb impulse theory, exact
//    here because the plane's normal is fixed, so the normal motion does not depend on the
//    tangential one). For a sphere with v = (v_t, 0, -v_n), omega = 0 on the plane z = 0:
//        v_t'  = v_t - mu (1 + e) v_n
//        w_y'  = mu (1 + e) v_n m Rbar / I = 2.5 mu (1 + e) v_n Rbar / R^2
//        u'    = v_t' - R w_y' = v_t - mu (1 + e) v_n (1 + m R Rbar / I)   (contact point)
//    where Rbar is the lever arm of the friction force averaged over the normal impulse. The
//    contact point, and so the lever arm, lies at R - d/2 (the middle of the overlap d), so
//    Rbar = R - 0.5 <d>, and for an elastic Hertz impact <d> = int d F dt / int F dt =
//    B(1.4, 0.5) / 2 d_max = 0.8176 d_max (closed form: substitute the energy integral
//    m d'^2 / 2 + 2/5 k d^2.5 = m v^2 / 2). Rigid-body theory (Rbar = R) differs from this by
//    0.4 d_max / R: 0.1 % for alumina at 3.9 m/s but 1.1 % for polyethylene at 5 m/s.
//    The contact point keeps sliding as long as u stays positive: with u(end) = v_t - 3.5 mu
//    (1 + e) v_n (I = 0.4 m R^2) the sliding regime is tan(theta) = v_t / v_n > 3.5 mu (1 + e).
//  - Oblique impacts below that threshold (sticking and microslip). Bounds valid in every
//    regime: the friction impulse never exceeds mu J_n (so the contact point's rebound u' never
//    falls below the sliding line), and the angular impulse about the contact point vanishes
//    up to the lever arm's variation (|I w' - R J_t| <= d_max / 2 mu J_n). The no-slip limit
//    (mu -> infinity) of the model is a linear tangential spring of stiffness 8 G* sqrt(R d(t))
//    driven by the Hertz normal motion; we integrate it independently with RK4 and compare, and
//    the smallest incidences must follow it. Note that in this limit the spring, which
//    oscillates ~1.7 times faster than the normal contact, nearly completes a period: u' / u is
//    +0.95 for alumina and steel (and can exceed 1: the incremental spring whose stiffness
//    changes with the overlap does not conserve energy), not the reversal that Maw, Barber &
//    Fawcett (Wear 38 (1976) 101) find for full Mindlin-Deresiewicz microslip at small
//    incidence. The model does reproduce MBF's reversal in the microslip range just below the
//    sliding threshold (negative contact-point rebound angle, u' < 0; Kharaz et al. measured it
//    for 5 to 30 degrees in paper test 4), with the minimum of the normalised recoil
//    u' / (mu v_n) in that range; these are the qualitative checks.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "scene_builders.hpp"
#include "src/restitution.hpp"

namespace kdem::testing {
namespace {

constexpr double degree = M_PI / 180.0;

struct BodyState {
  Vec3d x{0, 0, 0}, v{0, 0, 0}, w{0, 0, 0};
};

BodyState body(const ParticleSnapshot& s, std::int64_t id) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.id[i] != id)
      continue;
    BodyState b;
    for (int c = 0; c < 3; ++c) {
      b.x[c] = s.position[3 * i + c];
      b.v[c] = s.velocity[3 * i + c];
      b.w[c] = s.angular_velocity[3 * i + c];
    }
    return b;
  }
  ADD_FAILURE() << "no particle with id " << id;
  return {};
}

double sphere_mass(const MaterialConfig& m, double radius) {
  return m.density * 4.0 / 3.0 * M_PI * radius * radius * radius;
}

double effective_shear(const MaterialConfig& a, const MaterialConfig& b) {
  return 1.0 / (2 * (2 - a.poisson_ratio) * (1 + a.poisson_ratio) / a.youngs_modulus +
                2 * (2 - b.poisson_ratio) * (1 + b.poisson_ratio) / b.youngs_modulus);
}

// The "rigid plane" of the paper: the sphere's material, 1000 times stiffer.
MaterialConfig rigid_plane_of(const MaterialConfig& m) {
  MaterialConfig p = m;
  p.name = m.name + "_plane";
  p.youngs_modulus = 1000 * m.youngs_modulus;
  return p;
}

// What one impact of particle 0 produced. The normal coordinate is `gap(x)`, the distance
// between the surfaces (negative while overlapping).
struct Impact {
  BodyState after;         // the first state after the surfaces separated
  double peak_overlap = 0; // m
  double peak_force = 0;   // N, m |dv_n| / dt over one step (the mean force of that step)
  double duration = 0;     // s, touching instants interpolated linearly in the gap
};

Impact record_impact(Engine& engine, double mass, const Vec3d& normal,
                     const std::function<double(const ParticleSnapshot&, const BodyState&)>& gap_of,
                     std::int64_t step_limit = 200000) {
  Impact r;
  const double dt = engine.time_step();
  double previous_gap = 0, previous_vn = 0, touch_start = -1;
  for (std::int64_t k = 0; k < step_limit; ++k) {
    const ParticleSnapshot snap = engine.snapshot();
    const BodyState b = body(snap, 0);
    const double gap = gap_of(snap, b);
    const double vn = b.v[0] * normal[0] + b.v[1] * normal[1] + b.v[2] * normal[2];
    if (k > 0) {
      r.peak_force = std::max(r.peak_force, mass * std::abs(vn - previous_vn) / dt);
      if (previous_gap >= 0 && gap < 0)
        touch_start = engine.time() - dt * gap / (gap - previous_gap);
      if (previous_gap < 0 && gap >= 0) {
        r.duration = engine.time() - dt * gap / (gap - previous_gap) - touch_start;
        r.after = b;
        return r;
      }
    }
    r.peak_overlap = std::max(r.peak_overlap, -gap);
    previous_gap = gap;
    previous_vn = vn;
    engine.step();
  }
  ADD_FAILURE() << "the impact did not end within " << step_limit << " steps";
  return r;
}

// --- Paper test 1: two identical spheres ----------------------------------------------------

struct SphereCase {
  const char* name;
  double density, youngs, poisson;
};

class ChungOoiTest1 : public ::testing::TestWithParam<SphereCase> {};

// Paper: R = 10 mm, each sphere at 10 m/s towards the other, glass (48 GPa, 0.20, 2800 kg/m^3)
// and limestone (20 GPa, 0.25, 2500 kg/m^3). Alumina (380 GPa, 0.23, 4000 kg/m^3) and a
// nylon-like polymer (2.5 GPa, 0.40, 1150 kg/m^3) extend the range of stiffness (d_max / R from
// 0.8 % to 6 %; the Hertz force law in the overlap is exact for the model at any overlap).
// dt = t_c / 1000: velocity Verlet's errors are O((dt / t_c)^2) ~ 1e-6, and sampling the peak
// between steps misses at most (pi dt / (2 t_c))^2 / 2 ~ 1e-6 of it (observed: 1.4e-6 for all
// materials, the problem being scale-free), so 1e-4 leaves a wide margin while catching any
// error in the law's constants (a 1e-3 error in the Hertz stiffness moves these by 4e-4).
TEST_P(ChungOoiTest1, HeadOnImpactOfIdenticalSpheresMatchesHertz) {
  const SphereCase& c = GetParam();
  const MaterialConfig m = material(c.name, c.density, c.youngs, c.poisson, 1.0, 0.35);
  const double radius = 0.010, speed = 10.0; // each sphere; relative speed 20 m/s
  const double mass = sphere_mass(m, radius);
  const HertzImpact h = hertz_impact(0.5 * mass, 0.5 * radius, effective_youngs(m, m), 2 * speed);
  SceneConfig scene = empty_scene(h.duration / 1000, {m});
  Engine engine(scene);
  const double start_gap = 5.5 * 2 * speed * engine.time_step();
  engine.add_particles({sphere({-radius - 0.5 * start_gap, 0, 0}, radius, {speed, 0, 0}),
                        sphere({radius + 0.5 * start_gap, 0, 0}, radius, {-speed, 0, 0})});
  auto gap = [&](const ParticleSnapshot& s, const BodyState& b0) {
    return body(s, 1).x[0] - b0.x[0] - 2 * radius;
  };
  const Impact r = record_impact(engine, mass, {1, 0, 0}, gap);
  const BodyState b1 = body(engine.snapshot(), 1);
  EXPECT_NEAR(r.peak_overlap, h.peak_overlap, 1e-4 * h.peak_overlap);
  EXPECT_NEAR(r.peak_force, h.peak_force, 1e-4 * h.peak_force);
  EXPECT_NEAR(r.duration, h.duration, 1e-4 * h.duration);
  // Elastic: both rebound at the approach speed (velocity Verlet is time-reversible, so the
  // rebound speed's error is far below the O((dt / t_c)^2) = 1e-6 bound used here; observed
  // 3e-11); momentum is conserved to round-off (equal and opposite pair forces); a head-on
  // impact makes no spin.
  EXPECT_NEAR(r.after.v[0], -speed, 1e-6 * speed);
  EXPECT_NEAR(r.after.v[0] + b1.v[0], 0.0, 1e-12 * speed);
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(r.after.w[k], 0.0);
}

INSTANTIATE_TEST_SUITE_P(Materials, ChungOoiTest1,
                         ::testing::Values(SphereCase{"glass", 2800, 4.8e10, 0.20},
                                           SphereCase{"limestone", 2500, 2.0e10, 0.25},
                                           SphereCase{"alumina", 4000, 3.8e11, 0.23},
                                           SphereCase{"nylon", 1150, 2.5e9, 0.40}),
                         [](const auto& info) { return std::string(info.param.name); });

// --- Paper tests 2 and 3: a sphere on a rigid plane -------------------------------------------

// Sphere of `m` starting just above the plane z = 0 with velocity v and spin w; returns the
// impact record. dt = t_c / steps_per_contact for the normal speed.
Impact plane_impact(const MaterialConfig& m, double radius, Vec3d v, Vec3d w, int steps_per_contact,
                    HertzImpact* hertz = nullptr) {
  const MaterialConfig plane = rigid_plane_of(m);
  const double mass = sphere_mass(m, radius);
  const double vn = -v[2];
  const HertzImpact h = hertz_impact(mass, radius, effective_youngs(m, plane), vn);
  if (hertz)
    *hertz = h;
  SceneConfig scene = empty_scene(h.duration / steps_per_contact, {m, plane});
  scene.walls.push_back(plane_wall(plane.name, {0, 0, 0}, {0, 0, 1}));
  Engine engine(scene);
  ParticleInit p = sphere({0, 0, radius + 5.5 * vn * engine.time_step()}, radius, v);
  p.angular_velocity = w;
  engine.add_particles({p});
  return record_impact(engine, mass, {0, 0, 1}, [&](const ParticleSnapshot&, const BodyState& b) {
    return b.x[2] - radius;
  });
}

struct PlaneCase {
  const char* name;
  double density, youngs, poisson, radius, speed;
};

class ChungOoiTest2Elastic : public ::testing::TestWithParam<PlaneCase> {};

// Paper test 2: R = 0.1 m at 0.2 m/s, aluminium alloy (70 GPa, 0.30, 2699 kg/m^3) and
// magnesium alloy (40 GPa, 0.35, 1800 kg/m^3); paper test 3's alumina and cast iron at 3.9 m/s,
// R = 2.5 mm, e = 1. Tolerances as in test 1 (dt = t_c / 1000; observed 1.4e-6 and 3e-11).
TEST_P(ChungOoiTest2Elastic, SphereOnRigidPlaneMatchesHertz) {
  const PlaneCase& c = GetParam();
  const MaterialConfig m = material(c.name, c.density, c.youngs, c.poisson, 1.0, 0.0);
  HertzImpact h;
  const Impact r = plane_impact(m, c.radius, {0, 0, -c.speed}, {0, 0, 0}, 1000, &h);
  EXPECT_NEAR(r.peak_overlap, h.peak_overlap, 1e-4 * h.peak_overlap);
  EXPECT_NEAR(r.peak_force, h.peak_force, 1e-4 * h.peak_force);
  EXPECT_NEAR(r.duration, h.duration, 1e-4 * h.duration);
  EXPECT_NEAR(r.after.v[2], c.speed, 1e-6 * c.speed);
}

INSTANTIATE_TEST_SUITE_P(
    Materials, ChungOoiTest2Elastic,
    ::testing::Values(PlaneCase{"aluminium_alloy", 2699, 7.0e10, 0.30, 0.10, 0.2},
                      PlaneCase{"magnesium_alloy", 1800, 4.0e10, 0.35, 0.10, 0.2},
                      PlaneCase{"alumina", 4000, 3.8e11, 0.23, 0.0025, 3.9},
                      PlaneCase{"cast_iron", 7000, 1.0e11, 0.25, 0.0025, 3.9}),
    [](const auto& info) { return std::string(info.param.name); });

// Paper test 3: alumina and cast iron, R = 2.5 mm, 3.9 m/s, e = 0.2 ... 1.0. The damping is
// calibrated so that the continuous model gives e to ~1e-6 (see test_hertz_impacts.cpp);
// what remains is the time discretisation: the damping force uses the half-step velocity, an
// error of first order in dt whose weight grows with the damping (observed with dt = t_c / 1000:
// -9.6e-4 at e = 0.2, -4.6e-5 at e = 0.8, 3e-11 at e = 1). The tolerance is 5e-3 relative.
// Damping must also lower the peak overlap below Hertz's elastic value.
TEST(ChungOoiTest2, RestitutionOnRigidPlane) {
  for (const PlaneCase& c : {PlaneCase{"alumina", 4000, 3.8e11, 0.23, 0.0025, 3.9},
                             PlaneCase{"cast_iron", 7000, 1.0e11, 0.25, 0.0025, 3.9}}) {
    for (double e : {0.2, 0.4, 0.6, 0.8, 1.0}) {
      const MaterialConfig m = material(c.name, c.density, c.youngs, c.poisson, e, 0.0);
      HertzImpact h;
      const Impact r = plane_impact(m, c.radius, {0, 0, -c.speed}, {0, 0, 0}, 1000, &h);
      EXPECT_NEAR(r.after.v[2] / c.speed, e, 5e-3 * e) << c.name << " e = " << e;
      if (e < 1)
        EXPECT_LT(r.peak_overlap, h.peak_overlap) << c.name << " e = " << e;
    }
  }
}

// --- Paper tests 4 and 5: oblique impacts ----------------------------------------------------

// Outcome of an oblique impact with v = (vt, 0, -vn), no initial spin, expressed as the
// benchmark's quantities.
struct Oblique {
  double vt = 0, vn = 0;
  double vt_after = 0, vn_after = 0;
  double spin_after = 0;                                                  // w_y', rad/s
  double contact_point_after = 0;                                         // u' = vt' - R w_y'
  double rebound_angle() const { return std::atan2(vt_after, vn_after); } // from the normal
};

Oblique oblique_impact(const MaterialConfig& m, double radius, double vt, double vn) {
  const Impact r = plane_impact(m, radius, {vt, 0, -vn}, {0, 0, 0}, 1000);
  Oblique o;
  o.vt = vt;
  o.vn = vn;
  o.vt_after = r.after.v[0];
  o.vn_after = r.after.v[2];
  o.spin_after = r.after.w[1];
  o.contact_point_after = r.after.v[0] - radius * r.after.w[1];
  EXPECT_NEAR(r.after.v[1], 0.0, 1e-12 * (vt + vn));
  return o;
}

// Gross sliding prediction (see the header), with the lever arm R - 0.5 <d>.
struct SlidingPrediction {
  double vt_after, spin_after, contact_point_after;
};

SlidingPrediction sliding_prediction(const MaterialConfig& m, double radius, double vt, double vn,
                                     double mu, double e) {
  const double mass = sphere_mass(m, radius), inertia = 0.4 * mass * radius * radius;
  const HertzImpact h = hertz_impact(mass, radius, effective_youngs(m, rigid_plane_of(m)), vn);
  const double mean_overlap =
      std::tgamma(1.4) * std::tgamma(0.5) / std::tgamma(1.9) / 2 * h.peak_overlap; // 0.8176 d_max
  const double lever = radius - 0.5 * mean_overlap;
  const double friction_impulse = mu * (1 + e) * vn * mass;
  SlidingPrediction p;
  p.vt_after = vt - friction_impulse / mass;
  p.spin_after = friction_impulse * lever / inertia;
  p.contact_point_after = p.vt_after - radius * p.spin_after;
  return p;
}

// The no-slip limit of the model (mu -> infinity), integrated with RK4: with d the overlap,
// S_n = 2 E* sqrt(R d), k_t = 8 G* sqrt(R d), gamma = damping_for_restitution(e),
//   m d'' = -(4/3 E* sqrt(R) d^1.5 + gamma sqrt(S_n m) d'),
//   xi' = u = v_t - (R - d/2) w_y,   F_t = -k_t xi - gamma sqrt(k_t m) u,
//   m v_t' = F_t,   I w_y' = -(R - d/2) F_t.
// Returns u' / u at separation.
double no_slip_contact_point_ratio(const MaterialConfig& m, double radius, double vt, double vn) {
  const MaterialConfig plane = rigid_plane_of(m);
  const double mass = sphere_mass(m, radius), inertia = 0.4 * mass * radius * radius;
  const double youngs = effective_youngs(m, plane), shear = effective_shear(m, plane);
  const double gamma = damping_for_restitution(m.restitution);
  const HertzImpact h = hertz_impact(mass, radius, youngs, vn);
  using State = std::array<double, 5>; // d, d', v_t, w_y, xi
  auto rate = [&](const State& s) {
    const double d = std::max(s[0], 0.0), arm = radius - 0.5 * d, a = std::sqrt(radius * d);
    const double u = s[2] - arm * s[3];
    const double fn = 4.0 / 3.0 * youngs * a * d + gamma * std::sqrt(2 * youngs * a * mass) * s[1];
    const double kt = 8 * shear * a;
    const double ft = -kt * s[4] - gamma * std::sqrt(kt * mass) * u;
    return State{s[1], -fn / mass, ft / mass, -arm * ft / inertia, u};
  };
  auto axpy = [](const State& a, double f, const State& b) {
    State r;
    for (int k = 0; k < 5; ++k)
      r[k] = a[k] + f * b[k];
    return r;
  };
  const double step = h.duration / 40000;
  State s{0, vn, vt, 0, 0};
  for (int n = 0; n < 200000; ++n) {
    const State k1 = rate(s), k2 = rate(axpy(s, 0.5 * step, k1));
    const State k3 = rate(axpy(s, 0.5 * step, k2)), k4 = rate(axpy(s, step, k3));
    State next;
    for (int k = 0; k < 5; ++k)
      next[k] = s[k] + step / 6 * (k1[k] + 2 * k2[k] + 2 * k3[k] + k4[k]);
    if (n > 0 && next[0] <= 0) {
      const State end = axpy(s, s[0] / (s[0] - next[0]), axpy(next, -1, s));
      return (end[2] - radius * end[3]) / vt;
    }
    s = next;
  }
  ADD_FAILURE() << "reference impact did not end";
  return 0;
}

// Checks shared by tests 4 and 5 of the paper, for one impact with friction mu, restitution e.
void check_oblique(const Oblique& o, const MaterialConfig& m, double radius, double mu, double e,
                   const std::string& label) {
  const double mass = sphere_mass(m, radius), inertia = 0.4 * mass * radius * radius;
  const double normal_impulse = mass * (1 + e) * o.vn;
  const double friction_impulse = mass * (o.vt - o.vt_after);
  const HertzImpact h = hertz_impact(mass, radius, effective_youngs(m, rigid_plane_of(m)), o.vn);
  const double threshold = 3.5 * mu * (1 + e);
  // Friction does not change the normal restitution on a plane (the normal motion is
  // independent of the tangential one): 5e-3 as for the normal impacts.
  EXPECT_NEAR(o.vn_after / o.vn, e, 5e-3 * e) << label;
  // Coulomb bound on the friction impulse, J_t <= mu J_n+. The positive part J_n+ of the normal
  // impulse exceeds J_n only by the attractive damping tail at the end of contact, 4e-5 of J_n
  // for e = 0.98 and 0 for e = 1 (from the scaled equation of src/restitution.hpp); 1e-3 adds
  // room for the time discretisation (observed excess: 1e-4).
  EXPECT_LE(friction_impulse, mu * normal_impulse * (1 + 1e-3)) << label;
  // Angular impulse about the contact point: I w' = int (R - d/2) F_t dt, so
  // |I w' - R J_t| <= d_max / 2 int |F_t| dt <= d_max / 2 mu J_n+ (same 1e-3 allowance). A wrong
  // sign or lever arm of the friction torque breaks this by ~R J_t.
  EXPECT_LE(std::abs(inertia * o.spin_after - radius * friction_impulse),
            0.5 * h.peak_overlap * mu * normal_impulse * (1 + 1e-3))
      << label;
  // Gross sliding, used with a 25 % margin above the threshold derived in the header so that
  // the contact point certainly slides from first touch to separation: rigid-body Coulomb
  // impulse theory with the model's lever arm, to 1 % (observed: 1e-4).
  if (o.vt / o.vn > 1.25 * threshold) {
    const SlidingPrediction p = sliding_prediction(m, radius, o.vt, o.vn, mu, e);
    EXPECT_NEAR(o.vt_after, p.vt_after, 0.01 * std::abs(p.vt_after)) << label;
    EXPECT_NEAR(o.spin_after, p.spin_after, 0.01 * std::abs(p.spin_after)) << label;
    EXPECT_NEAR(o.contact_point_after, p.contact_point_after,
                0.01 * std::abs(p.contact_point_after))
        << label;
    const double predicted_angle = std::atan2(p.vt_after, e * o.vn);
    EXPECT_NEAR(o.rebound_angle(), predicted_angle, 0.01 * predicted_angle) << label;
  }
  // Microslip just below the sliding threshold (Maw, Barber & Fawcett; measured by Kharaz et
  // al. for 5 to 30 degrees): the contact point's tangential velocity reverses.
  if (o.vt / o.vn > 0.4 * threshold && o.vt / o.vn < threshold) {
    EXPECT_LT(o.contact_point_after, 0.0) << label;
  }
}

// The no-slip limit of the model (mu = 1e6, elastic) against the independent RK4 integration.
// The engine converges to it at first order in dt (observed 1.7e-3 at t_c / 1000, 4e-4 at
// t_c / 4000; RK4 with t_c / 40000 is exact to ~1e-8), so 1 % is the tolerance. Returns the
// reference u' / u.
double check_no_slip_limit(const SphereCase& c, double radius, double vt, double vn, double e) {
  const MaterialConfig sticky = material(c.name, c.density, c.youngs, c.poisson, e, 1e6);
  const Oblique o = oblique_impact(sticky, radius, vt, vn);
  const double reference = no_slip_contact_point_ratio(sticky, radius, vt, vn);
  EXPECT_NEAR(o.contact_point_after / vt, reference, 0.01 * std::abs(reference)) << c.name;
  return reference;
}

// Paper test 4 (Kharaz, Gorham & Salman's experiment, Powder Technol. 120 (2001) 281): alumina
// sphere (380 GPa, 0.23, 4000 kg/m^3), R = 2.5 mm, 3.9 m/s, mu = 0.092, e = 0.98, incidence
// from the normal 0 ... 89 degrees (90 would never touch). Sliding for tan(theta) > 3.5 mu
// (1 + e) = 0.638 (32.5 degrees).
TEST(ChungOoiTest3, ObliqueImpactAtConstantSpeed) {
  const double mu = 0.092, e = 0.98, radius = 0.0025, speed = 3.9;
  const SphereCase alumina{"alumina", 4000, 3.8e11, 0.23};
  const MaterialConfig m =
      material("alumina", alumina.density, alumina.youngs, alumina.poisson, e, mu);
  const double no_slip = check_no_slip_limit(alumina, radius, speed * std::sin(2 * degree),
                                             speed * std::cos(2 * degree), e);
  double previous_angle = -1;
  for (double angle : {0.0, 2.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0}) {
    const double vt = speed * std::sin(angle * degree), vn = speed * std::cos(angle * degree);
    const Oblique o = oblique_impact(m, radius, vt, vn);
    const std::string label = "incidence " + std::to_string(angle) + " deg";
    if (angle == 0) {
      // Head-on: no tangential motion can arise (exact zeros: every tangential term vanishes).
      EXPECT_EQ(o.vt_after, 0.0);
      EXPECT_EQ(o.spin_after, 0.0);
      EXPECT_NEAR(o.vn_after / vn, e, 5e-3 * e);
      continue;
    }
    check_oblique(o, m, radius, mu, e, label);
    // At 2 degrees the tangential force stays below the Coulomb limit (F_t / mu F_n starts at
    // 6 G* v_t / (E* mu v_n) = 0.5 and does not grow much), so the impact follows the no-slip
    // limit: 1 % as in check_no_slip_limit (observed 0.2 %).
    if (angle == 2.0)
      EXPECT_NEAR(o.contact_point_after / vt, no_slip, 0.01 * std::abs(no_slip)) << label;
    // The centroid's rebound angle grows with the incidence angle (Kharaz et al., Fig. 7).
    EXPECT_GT(o.rebound_angle(), previous_angle) << label;
    previous_angle = o.rebound_angle();
  }
}

// Paper test 5: constant normal speed 5 m/s, tangential speeds 0.1 ... 70 m/s, elastic (e = 1),
// mu = 0.3, steel (208 GPa, 0.30, 7850 kg/m^3) and polyethylene (1 GPa, 0.40, 1400 kg/m^3) as in
// the PySPH example of the benchmark; the sphere's radius is not known to us from the paper,
// we use 10 mm (every normalised result below is independent of the radius). Sliding for
// v_t / v_n > 3.5 mu (1 + e) = 2.1.
class ChungOoiTest4 : public ::testing::TestWithParam<SphereCase> {};

TEST_P(ChungOoiTest4, ObliqueImpactAtConstantNormalSpeed) {
  const SphereCase& c = GetParam();
  const double mu = 0.3, e = 1.0, radius = 0.010, vn = 5.0;
  const MaterialConfig m = material(c.name, c.density, c.youngs, c.poisson, e, mu);
  const double no_slip = check_no_slip_limit(c, radius, 0.1, vn, e);
  double lowest_recoil = 1e300, lowest_at = 0;
  auto csv = validation_csv(std::string("chung_ooi_test4_") + c.name,
                            "incidence,recoil,spin,sliding_recoil,sliding_spin,no_slip_recoil");
  for (double vt : {0.1, 0.3, 0.5, 1.0, 2.0, 5.0, 10.0, 15.0, 20.0, 30.0, 50.0, 70.0}) {
    const Oblique o = oblique_impact(m, radius, vt, vn);
    if (csv) {
      const SlidingPrediction p = sliding_prediction(m, radius, vt, vn, mu, e);
      *csv << vt / (mu * vn) << "," << o.contact_point_after / (mu * vn) << ","
           << radius * o.spin_after / (mu * vn) << "," << p.contact_point_after / (mu * vn) << ","
           << radius * p.spin_after / (mu * vn) << "," << no_slip * vt / (mu * vn) << "\n";
    }
    const std::string label = std::string(c.name) + " v_t = " + std::to_string(vt);
    check_oblique(o, m, radius, mu, e, label);
    // Small incidence: the no-slip limit (a linear problem, so u' / u does not depend on v_t;
    // only the slip in the last instants of contact differs), 1 % (observed 0.2 %).
    if (vt <= 0.3)
      EXPECT_NEAR(o.contact_point_after / vt, no_slip, 0.01 * std::abs(no_slip)) << label;
    const double recoil = o.contact_point_after / (mu * vn);
    if (recoil < lowest_recoil)
      lowest_recoil = recoil, lowest_at = vt;
  }
  // Maw, Barber & Fawcett's curve of the normalised recoil u' / (mu v_n) against the normalised
  // incidence v_t / (mu v_n): its minimum is negative and lies in the microslip range, between
  // the sticking impacts of small v_t and the sliding threshold.
  EXPECT_LT(lowest_recoil, 0.0) << c.name;
  EXPECT_GT(lowest_at / vn, 0.2 * 3.5 * mu * (1 + e)) << c.name;
  EXPECT_LT(lowest_at / vn, 3.5 * mu * (1 + e)) << c.name;
}

INSTANTIATE_TEST_SUITE_P(Materials, ChungOoiTest4,
                         ::testing::Values(SphereCase{"steel", 7850, 2.08e11, 0.30},
                                           SphereCase{"polyethylene", 1400, 1.0e9, 0.40}),
                         [](const auto& info) { return std::string(info.param.name); });

} // namespace
} // namespace kdem::testing
