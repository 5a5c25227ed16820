// The checks that stop a run gone wrong (docs/scene.md, "checks"): non-finite state, overlaps
// beyond a fraction of the radius, kinetic energy beyond what the scene can give its particles,
// particles outside the domain; each names the particles involved and the likely causes.
#include <cmath>
#include <cstdio>

#include "../kernels/diagnostics.hpp"
#include "engine_state.hpp"
#include "host_copy.hpp"

namespace kdem {
namespace {

std::string printed(const char* format, double a, double b = 0, double c = 0) {
  char text[256];
  std::snprintf(text, sizeof text, format, a, b, c);
  return text;
}

std::vector<int> rows_on_host(const IndexView& rows) {
  return flatten_to_host(rows, int(rows.extent(0)));
}

template <class View> auto value_at(const View& view, int k) {
  auto one = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kokkos::subview(view, k));
  return one();
}

std::string particles_text(int count) {
  return std::to_string(count) + (count == 1 ? " particle" : " particles");
}

// A wall moving more than this fraction of the smallest radius per step is named as a likely
// cause (a drum or belt moves well under 1 %).
constexpr double wall_travel_per_step_limit = 0.05;

} // namespace

HealthReport Engine::check_health() const {
  return state_->check_health();
}

HealthReport Engine::State::check_health() const {
  if (particles.count == 0)
    return {};
  IndexView flag("health_flag", particles.count);
  HealthReport report;
  if (const int bad = mark_non_finite(particles, flag); bad > 0) {
    report.trigger = "non_finite";
    report.finding = particles_text(bad) + " with a position, velocity, angular velocity or " +
                     "orientation that is not finite";
    report.particles = reports_of(rows_on_host(first_flagged_rows(flag, 5)));
  } else if (report = check_overlaps(); report.healthy()) {
    report = check_energy();
  }
  if (report.healthy() && scene.checks.leaving_domain == ChecksConfig::Leaving::Stop) {
    if (const int outside = mark_outside(particles, leaving_bounds, flag); outside > 0) {
      report.trigger = "left_domain";
      report.finding = particles_text(outside) + " left the domain " +
                       printed("[%g, %g, %g]", leaving_bounds.min[0], leaving_bounds.min[1],
                               leaving_bounds.min[2]) +
                       printed(" .. [%g, %g, %g] (checks.leaving_domain = stop)",
                               leaving_bounds.max[0], leaving_bounds.max[1], leaving_bounds.max[2]);
      report.particles = reports_of(rows_on_host(first_flagged_rows(flag, 5)));
    }
  }
  if (!report.healthy())
    report.likely_causes = likely_causes(report.trigger);
  return report;
}

// The deepest contact, pair or wall, against checks.max_overlap_ratio.
HealthReport Engine::State::check_overlaps() const {
  const ValueAndIndex pair = deepest_pair_contact(particles, pairs);
  const ValueAndIndex wall = deepest_wall_contact(particles, wall_contacts);
  const double limit = scene.checks.max_overlap_ratio;
  HealthReport report;
  if (std::max(pair.val, wall.val) <= limit)
    return report;
  report.trigger = "overlap";
  const std::string limit_text = printed(" (checks.max_overlap_ratio = %g)", limit);
  if (pair.val >= wall.val) {
    report.finding =
        printed("two particles overlap by %.3g of the smaller radius", pair.val) + limit_text;
    report.particles =
        reports_of({value_at(pairs.pair_i, pair.loc), value_at(pairs.pair_j, pair.loc)});
  } else {
    const int element = value_at(wall_contacts.element, wall.loc);
    const std::string& wall_name = scene.walls[table.wall[element]].name;
    report.finding = "a particle overlaps wall '" + wall_name +
                     printed("' by %.3g of its radius", wall.val) + limit_text;
    report.particles =
        reports_of({particle_of_wall_entry(wall_contacts, particles.count, wall.loc)});
  }
  return report;
}

// Without a work source the particles' kinetic energy cannot exceed the budget (the energy at
// the start, plus that inserted, less that removed) less their potential energy now. Moving walls
// do work that is not tracked: they add 0.5 M (v_wall + v_fall)^2, v_fall = sqrt(2 g D) over the
// domain's diagonal D. A floor of 0.5 M (0.01 v_ref)^2, v_ref = max(1 m/s, v_fall), keeps a bed
// at rest from tripping on round-off.
HealthReport Engine::State::check_energy() const {
  const EnergySums e = kinetic_and_potential_energy(particles, gravity);
  const double kinetic = e.translational + e.rotational;
  const double mass = total_mass(particles);
  double diagonal2 = 0;
  for (int k = 0; k < 3; ++k)
    diagonal2 += (domain_max[k] - domain_min[k]) * (domain_max[k] - domain_min[k]);
  const double fall_speed = std::sqrt(2 * norm(gravity) * std::sqrt(diagonal2));
  double wall_speed = 0;
  for (const WallMotionData& m : motions)
    wall_speed = std::max(wall_speed, wall_surface_speed(m));
  const double reference_speed = std::max(1.0, fall_speed);
  const double wall_allowance =
      wall_speed > 0 ? 0.5 * mass * (wall_speed + fall_speed) * (wall_speed + fall_speed) : 0;
  const double bound = std::max(energy_budget - e.potential, 0.0) + wall_allowance +
                       0.5 * mass * 0.0001 * reference_speed * reference_speed;
  const double gain = scene.checks.max_energy_gain;
  HealthReport report;
  if (kinetic <= (1 + gain) * bound)
    return report;
  report.trigger = "energy";
  report.finding =
      printed("kinetic energy %.3g J exceeds %.3g J, (1 + checks.max_energy_gain = ", kinetic,
              (1 + gain) * bound) +
      printed("%g) times what the scene can give its particles (%.3g J)", gain, bound);
  if (const ValueAndIndex fastest = fastest_particle(particles); fastest.loc >= 0)
    report.particles = reports_of({fastest.loc}); // none when all energy is rotational
  return report;
}

std::vector<std::string> Engine::State::likely_causes(const std::string& trigger) const {
  std::vector<std::string> causes;
  const TimeStepAdvice advice = time_step_advice();
  if (advice.suggested > 0 && dt > advice.suggested)
    causes.push_back(printed("time_step %.3g s is %.3g times the suggested %.3g s", dt,
                             dt / advice.suggested, advice.suggested));
  if (initial_overlap_ratio > 0.05)
    causes.push_back(
        printed("particles started overlapping by up to %.0f%% of their radius (a region "
                "reaching through a wall, or particles added overlapping)",
                100 * initial_overlap_ratio));
  for (std::size_t w = 0; w < motions.size(); ++w) {
    const double speed = wall_surface_speed(motions[w]);
    if (!(speed > 0))
      continue;
    const double contact_time = hertz_time_at(speed);
    const double step_travel = speed * dt / time_step_radius();
    if (step_travel > wall_travel_per_step_limit)
      causes.push_back("wall '" + scene.walls[w].name +
                       printed("' moves at up to %.3g m/s, %.2g of the smallest radius per time "
                               "step (above %.2g a step its contacts are poorly resolved)",
                               speed, step_travel, wall_travel_per_step_limit));
    else if (dt > 0.1 * contact_time) {
      causes.push_back("wall '" + scene.walls[w].name +
                       printed("' moves at up to %.3g m/s: a contact at that speed lasts %.3g s "
                               "and needs a time step below %.3g s",
                               speed, contact_time, 0.1 * contact_time));
    }
  }
  if (trigger == "left_domain")
    causes.push_back("particles escaping through an opening in the walls, or a domain too small");
  if (causes.empty())
    causes.push_back("none of the usual (time step, overlapping start, fast wall) applies: check "
                     "the materials' stiffness and density and the scene's units");
  return causes;
}

std::vector<ParticleReport> Engine::State::reports_of(const std::vector<int>& rows) const {
  const IndexView device_rows = upload<int>("report_rows", rows);
  const ParticleViews g = gathered_rows(particles, device_rows);
  const std::vector<std::int64_t> id = flatten_to_host(g.id, g.count);
  const std::vector<int> shape = flatten_to_host(g.shape, g.count);
  const std::vector<double> x = flatten_to_host(g.position, g.count);
  const std::vector<double> v = flatten_to_host(g.velocity, g.count);
  std::vector<ParticleReport> reports(rows.size());
  for (std::size_t m = 0; m < rows.size(); ++m) {
    ParticleReport& r = reports[m];
    r.id = id[m];
    r.shape = shape[m] == sphere_shape ? "sphere"
                                       : scene.shapes[shape[m] - 1].name + " (" +
                                             scene.shapes[shape[m] - 1].family + ")";
    for (int c = 0; c < 3; ++c)
      r.position[c] = x[3 * m + c], r.velocity[c] = v[3 * m + c];
  }
  return reports;
}

std::vector<std::int64_t> Engine::State::ids_of_flagged(const IndexView& flag, int most) const {
  const IndexView rows = first_flagged_rows(flag, most);
  const ParticleViews g = gathered_rows(particles, rows);
  return flatten_to_host(g.id, g.count);
}

std::int64_t Engine::lost_count() const {
  return state_->lost_count;
}

std::vector<std::int64_t> Engine::latest_lost_ids() const {
  return state_->latest_lost_ids;
}

} // namespace kdem
