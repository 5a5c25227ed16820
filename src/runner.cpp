#include "runner.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "atomic_file.hpp"
#include "build_info.hpp"
#include "engine.hpp"
#include "kernel_timer.hpp"
#include "progress.hpp"
#include "run_summary.hpp"
#include "scene_loader.hpp"
#include "series_csv.hpp"
#include "vtk_output.hpp"

namespace kdem {
namespace {

namespace fs = std::filesystem;

std::string numbered(const std::string& stem, std::int64_t number, const std::string& extension) {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%08lld", static_cast<long long>(number));
  return stem + "_" + digits + extension;
}

const std::vector<std::string> base_series_columns = {"step",
                                                      "time",
                                                      "translational_energy",
                                                      "rotational_energy",
                                                      "potential_energy",
                                                      "particles",
                                                      "pair_contacts",
                                                      "wall_contacts",
                                                      "largest_overlap_ratio",
                                                      "discharged_mass",
                                                      "discharged_count",
                                                      "list_builds",
                                                      "lost_mass",
                                                      "lost_count"};

std::vector<double> base_series_row(const Diagnostics& d);

// The base columns, then the particles of each source ("source:<name>") and of each tag
// ("tag:<tag>").
std::vector<std::string> series_columns(const Engine& engine) {
  std::vector<std::string> columns = base_series_columns;
  for (const std::string& name : engine.source_names())
    columns.push_back("source:" + name);
  for (const std::string& tag : engine.tag_names())
    columns.push_back("tag:" + tag);
  return columns;
}

std::vector<double> series_row(const Diagnostics& d) {
  std::vector<double> row = base_series_row(d);
  for (std::int64_t count : d.particles_per_source)
    row.push_back(double(count));
  for (std::int64_t count : d.particles_per_tag)
    row.push_back(double(count));
  return row;
}

std::vector<double> base_series_row(const Diagnostics& d) {
  return {double(d.step),
          d.time,
          d.translational_energy,
          d.rotational_energy,
          d.potential_energy,
          double(d.particles),
          double(d.pair_contacts),
          double(d.wall_contacts),
          d.largest_overlap_ratio,
          d.discharged_mass,
          double(d.discharged_count),
          double(d.list_builds),
          d.lost_mass,
          double(d.lost_count)};
}

// Steps between two events spaced `interval` seconds apart (at least one step).
std::int64_t steps_per(double interval, double dt, std::int64_t fallback) {
  if (!(interval > 0))
    return fallback;
  return std::max<std::int64_t>(1, std::llround(interval / dt));
}

void warn_about_time_step(const Engine& engine, bool quiet) {
  const TimeStepAdvice advice = engine.time_step_advice();
  if (quiet || !(advice.suggested > 0) || engine.time_step() <= advice.suggested)
    return;
  std::fprintf(
      stderr,
      "warning: time_step %.3g s exceeds the suggested %.3g s (20%% of the Rayleigh time %.3g s, "
      "10%% of the Hertz contact time %.3g s at %.2g m/s)\n",
      engine.time_step(), advice.suggested, advice.rayleigh, advice.hertz, advice.reference_speed);
}

// Particles placed across a wall (a region reaching through it) start with a large overlap
// and are shot away; say so before the run rather than leave the user to wonder.
void warn_about_initial_overlaps(const Engine& engine, bool quiet) {
  const Diagnostics d = engine.diagnostics();
  if (quiet || d.largest_overlap_ratio <= 0.05)
    return;
  std::fprintf(
      stderr,
      "warning: at the start particles overlap by up to %.0f%% of their radius (%d wall and %d "
      "particle contacts); does a particle region reach through a wall?\n",
      100 * d.largest_overlap_ratio, d.wall_contacts, d.pair_contacts);
}

std::string vector_json(const Vec3d& a) {
  return "[" + json_number(a[0]) + ", " + json_number(a[1]) + ", " + json_number(a[2]) + "]";
}

std::string failure_json(const Engine& engine, const HealthReport& report) {
  std::ostringstream out;
  out << "{\n  \"trigger\": " << json_string(report.trigger)
      << ",\n  \"step\": " << engine.step_count() << ",\n  \"time\": " << json_number(engine.time())
      << ",\n  \"finding\": " << json_string(report.finding) << ",\n  \"particles\": [";
  for (std::size_t k = 0; k < report.particles.size(); ++k) {
    const ParticleReport& p = report.particles[k];
    out << (k ? "," : "") << "\n    {\"id\": " << p.id << ", \"shape\": " << json_string(p.shape)
        << ", \"position\": " << vector_json(p.position)
        << ", \"velocity\": " << vector_json(p.velocity) << "}";
  }
  out << "\n  ],\n  \"likely_causes\": [";
  for (std::size_t k = 0; k < report.likely_causes.size(); ++k)
    out << (k ? "," : "") << "\n    " << json_string(report.likely_causes[k]);
  out << "\n  ]\n}\n";
  return out.str();
}

// One row per touching pair or particle-wall element: ids (partner -1 for a wall), the wall's
// index in the scene (-1 for a pair) and the force on the particle `id`, N.
std::string contact_forces_csv(const std::vector<ContactForceRecord>& records) {
  std::ostringstream out;
  out.precision(17);
  out << "id,partner,wall,fx,fy,fz\n";
  for (const ContactForceRecord& r : records)
    out << r.id << ',' << r.partner << ',' << r.wall << ',' << r.force[0] << ',' << r.force[1]
        << ',' << r.force[2] << '\n';
  return out.str();
}

class OutputWriter {
public:
  OutputWriter(const fs::path& directory, const SceneConfig& scene, const Engine& engine, double dt)
      : directory_(directory), particles_pvd_(directory, "particles"),
        surfaces_pvd_(directory, "shapes"), walls_pvd_(directory, "walls"),
        series_(directory / "series.csv", series_columns(engine)),
        frame_every_(steps_per(scene.output.frame_interval, dt, 0)),
        contact_forces_(scene.output.contact_forces),
        series_every_(steps_per(scene.output.series_interval, dt, 100)),
        checkpoint_every_(steps_per(scene.output.checkpoint_interval, dt, 0)) {
    fs::create_directories(directory / "frames");
  }

  void at_step(const Engine& engine, bool first) {
    const std::int64_t step = engine.step_count();
    if (frame_every_ > 0 && (first || step % frame_every_ == 0))
      write_frame(engine);
    if (first || step % series_every_ == 0)
      add_series_row(engine);
    if (checkpoint_every_ > 0 && !first && step % checkpoint_every_ == 0) {
      fs::create_directories(directory_ / "checkpoints");
      engine.write_checkpoint(
          (directory_ / "checkpoints" / numbered("checkpoint", step, ".h5")).string());
    }
  }

  void finish(const Engine& engine, bool final_checkpoint) {
    const std::int64_t step = engine.step_count();
    if (frame_every_ > 0 && step % frame_every_ != 0)
      write_frame(engine);
    if (step % series_every_ != 0)
      add_series_row(engine);
    series_.flush();
    if (final_checkpoint)
      engine.write_checkpoint((directory_ / "checkpoint.h5").string());
  }

  // The state of a run stopped by a check, beside its output: checkpoint, particle frame and
  // failure.json; series.csv flushed. Returns the files written.
  std::vector<fs::path> write_failure(const Engine& engine, const HealthReport& report) {
    series_.flush();
    const fs::path checkpoint = directory_ / "failure_checkpoint.h5";
    const fs::path frame = directory_ / "failure_particles.vtu";
    const fs::path json = directory_ / "failure.json";
    engine.write_checkpoint(checkpoint.string());
    write_particles_vtu(frame, engine.snapshot());
    write_text_atomically(json, failure_json(engine, report));
    return {checkpoint, frame, json};
  }

  const Diagnostics& last() const { return last_; }
  double largest_overlap_seen() const { return largest_overlap_; }

private:
  void write_frame(const Engine& engine) {
    const std::int64_t step = engine.step_count();
    const std::string particle_file = "frames/" + numbered("particles", step, ".vtu");
    const ParticleSnapshot snapshot = engine.snapshot();
    write_particles_vtu(directory_ / particle_file, snapshot);
    particles_pvd_.add(engine.time(), particle_file);
    if (!snapshot.shape_surfaces.empty()) {
      const std::string surface_file = "frames/" + numbered("shapes", step, ".vtp");
      write_particle_surfaces_vtp(directory_ / surface_file, snapshot);
      surfaces_pvd_.add(engine.time(), surface_file);
    }
    if (contact_forces_)
      write_text_atomically(directory_ / ("frames/" + numbered("contacts", step, ".csv")),
                            contact_forces_csv(engine.contact_forces()));
    const std::vector<WallSurface> walls = engine.wall_surfaces();
    for (std::size_t w = 0; w < walls.size(); ++w) {
      const std::string wall_file = "frames/" + numbered("wall" + std::to_string(w), step, ".vtp");
      write_wall_vtp(directory_ / wall_file, walls[w]);
      walls_pvd_.add(engine.time(), wall_file, int(w));
    }
  }

  void add_series_row(const Engine& engine) {
    last_ = engine.diagnostics();
    largest_overlap_ = std::max(largest_overlap_, last_.largest_overlap_ratio);
    series_.add_row(series_row(last_));
    if (++rows_since_flush_ >= 20) {
      series_.flush();
      rows_since_flush_ = 0;
    }
  }

  fs::path directory_;
  PvdSeries particles_pvd_, surfaces_pvd_, walls_pvd_;
  SeriesCsv series_;
  std::int64_t frame_every_;
  bool contact_forces_;
  std::int64_t series_every_, checkpoint_every_;
  Diagnostics last_;
  double largest_overlap_ = 0;
  int rows_since_flush_ = 0;
};

std::string particle_line(const ParticleReport& p) {
  char text[256];
  const double speed = std::sqrt(p.velocity[0] * p.velocity[0] + p.velocity[1] * p.velocity[1] +
                                 p.velocity[2] * p.velocity[2]);
  std::snprintf(text, sizeof text, " at (%.4g, %.4g, %.4g) m, speed %.3g m/s", p.position[0],
                p.position[1], p.position[2], speed);
  return "particle " + std::to_string(p.id) + " (" + p.shape + ")" + text;
}

// One message for a run stopped by a check: where, what, who, why, and what was written.
std::string failure_message(const Engine& engine, const HealthReport& report,
                            const std::vector<fs::path>& written) {
  std::ostringstream msg;
  msg << "run stopped at step " << engine.step_count() << " (t = " << engine.time() << " s), check "
      << report.trigger << ": " << report.finding;
  for (const ParticleReport& p : report.particles)
    msg << "\n  " << particle_line(p);
  for (const std::string& cause : report.likely_causes)
    msg << "\n  likely cause: " << cause;
  msg << "\n  state written to";
  for (std::size_t k = 0; k < written.size(); ++k)
    msg << (k == 0 ? " " : (k + 1 == written.size() ? " and " : ", ")) << written[k].string();
  return msg.str();
}

// Warns of particles leaving the domain: the first few removals by id, then a last word.
class LossWarnings {
public:
  explicit LossWarnings(bool quiet, std::int64_t lost_before) : quiet_(quiet), seen_(lost_before) {}
  void after_step(const Engine& engine) {
    const std::int64_t lost = engine.lost_count();
    if (lost == seen_)
      return;
    const std::int64_t newly = lost - seen_;
    seen_ = lost;
    if (quiet_ || warnings_ > max_warnings)
      return;
    if (warnings_++ == max_warnings) {
      std::fprintf(stderr, "warning: further particles leaving the domain are removed and counted "
                           "(series.csv and run.json: lost_count, lost_mass)\n");
      return;
    }
    std::string ids;
    for (std::int64_t id : engine.latest_lost_ids())
      ids += (ids.empty() ? "" : ", ") + std::to_string(id);
    std::fprintf(stderr,
                 "warning: %lld particles left the domain by t = %.6g s and were removed "
                 "(ids %s%s)\n",
                 static_cast<long long>(newly), engine.time(), ids.c_str(),
                 newly > 5 ? ", ..." : "");
  }

private:
  static constexpr int max_warnings = 5;
  bool quiet_;
  std::int64_t seen_;
  int warnings_ = 0;
};

RunSummary summarise(const Engine& engine, const OutputWriter& output, std::int64_t steps,
                     double seconds, double particle_steps, double initial_energy) {
  RunSummary summary;
  summary.version = KDEM_VERSION;
  summary.git_hash = git_hash();
  summary.backend = Engine::backend_name();
  summary.threads = Engine::backend_concurrency();
  const Diagnostics& d = output.last();
  summary.particles = d.particles;
  summary.steps = steps;
  summary.contacts = d.pair_contacts + d.wall_contacts;
  const NarrowPhaseTotals narrow = engine.narrow_phase_totals(); // iterative narrow phases only
  summary.narrow_phase_failures = narrow.failures;
  summary.wall_seconds = seconds;
  summary.particle_steps_per_second = seconds > 0 ? particle_steps / seconds : 0;
  summary.largest_overlap_ratio = output.largest_overlap_seen();
  summary.simulated_time = engine.time();
  summary.discharged_mass = d.discharged_mass;
  const double energy = d.translational_energy + d.rotational_energy + d.potential_energy;
  summary.energy_drift =
      initial_energy != 0 ? (energy - initial_energy) / std::abs(initial_energy) : 0;
  summary.extra.push_back({"time_step", engine.time_step()});
  summary.extra.push_back({"list_builds", double(d.list_builds)});
  summary.extra.push_back({"pair_candidates", double(engine.pair_candidates())});
  summary.extra.push_back({"wall_candidates", double(engine.wall_candidates())});
  summary.extra.push_back({"pair_contacts", double(d.pair_contacts)});
  summary.extra.push_back({"discharged_count", double(d.discharged_count)});
  summary.extra.push_back({"lost_count", double(d.lost_count)});
  summary.extra.push_back({"lost_mass", d.lost_mass});
  summary.extra.push_back({"narrow_phase_evaluations", double(narrow.evaluations)});
  summary.extra.push_back({"narrow_phase_fallbacks", double(narrow.fallbacks)});
  summary.extra.push_back(
      {"narrow_phase_mean_iterations",
       narrow.evaluations > 0 ? double(narrow.iterations) / double(narrow.evaluations) : 0.0});
  return summary;
}

// Exit status of a run stopped by a check (docs/scene.md, "checks").
constexpr int stopped_by_check = 3;

int stop_if_unhealthy(const Engine& engine, OutputWriter& output) {
  const HealthReport report = engine.check_health();
  if (report.healthy())
    return 0;
  const std::vector<fs::path> written = output.write_failure(engine, report);
  std::fprintf(stderr, "error: %s\n", failure_message(engine, report, written).c_str());
  return stopped_by_check;
}

} // namespace

int run_scene(const RunOptions& options) {
  std::optional<KernelTimer> timer; // before the engine, so that it sees every allocation
  if (options.kernel_times)
    timer.emplace();
  std::optional<Engine> engine;
  SceneConfig scene;
  try {
    scene = load_scene(options.scene_path);
    if (!options.output_directory.empty())
      scene.output.directory = options.output_directory;
    engine.emplace(scene);
    if (!options.restart_path.empty())
      engine->read_checkpoint(options.restart_path);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 2;
  }
  warn_about_time_step(*engine, options.quiet);
  warn_about_initial_overlaps(*engine, options.quiet);
  try {
    const fs::path directory = scene.output.directory;
    fs::remove(directory / "run.json"); // a run that fails must not leave an earlier one's
    OutputWriter output(directory, scene, *engine, engine->time_step());
    const std::int64_t total_steps = std::llround(scene.duration / scene.time_step);
    std::int64_t remaining = std::max<std::int64_t>(0, total_steps - engine->step_count());
    if (options.max_steps >= 0)
      remaining = std::min(remaining, options.max_steps);
    output.at_step(*engine, true);
    const Diagnostics& first = output.last();
    const double initial_energy =
        first.translational_energy + first.rotational_energy + first.potential_energy;
    const std::int64_t check_every = scene.checks.interval;
    if (const int code = stop_if_unhealthy(*engine, output); code != 0)
      return code;
    LossWarnings losses(options.quiet, engine->lost_count());
    ProgressLine progress(options.quiet, engine->step_count() + remaining);
    if (timer)
      timer->reset(); // the kernels of the steps only
    const auto start = std::chrono::steady_clock::now();
    double particle_steps = 0;
    for (std::int64_t k = 0; k < remaining; ++k) {
      particle_steps += engine->particle_count();
      engine->step();
      losses.after_step(*engine);
      if (engine->step_count() % check_every == 0)
        if (const int code = stop_if_unhealthy(*engine, output); code != 0) {
          progress.finish();
          return code;
        }
      output.at_step(*engine, false);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      progress.update(engine->step_count(), engine->time(),
                      seconds > 0 ? particle_steps / seconds : 0);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress.finish();
    if (timer)
      timer->write_json(directory / "kernel_times.json", remaining, std::int64_t(particle_steps),
                        engine->particle_count());
    output.finish(*engine, scene.output.final_checkpoint);
    write_run_json(directory / "run.json",
                   summarise(*engine, output, remaining, seconds, particle_steps, initial_energy));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  }
  return 0;
}

int check_scene(const std::string& scene_path) {
  try {
    const SceneConfig scene = load_scene(scene_path);
    Engine engine(scene);
    const TimeStepAdvice advice = engine.time_step_advice();
    std::printf("%s: %d particles, %zu walls, %zu materials\n", scene_path.c_str(),
                engine.particle_count(), scene.walls.size(), scene.materials.size());
    std::printf("time step %.3g s; suggested %.3g s (Rayleigh %.3g s, Hertz %.3g s at %.2g m/s)\n",
                engine.time_step(), advice.suggested, advice.rayleigh, advice.hertz,
                advice.reference_speed);
    std::printf("steps %lld, skin %.3g m\n",
                static_cast<long long>(std::llround(scene.duration / scene.time_step)),
                engine.skin());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 2;
  }
  return 0;
}

} // namespace kdem
