#pragma once
// The engine: owns the particle, contact and wall stores in the execution space's memory, and
// runs the time step of docs/architecture.md ("One time step"). Host code outside this class never
// touches device data.
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "scene.hpp"
#include "snapshot.hpp"

namespace kdem {

struct ParticleInit {
  Vec3d position{0, 0, 0};
  Vec3d velocity{0, 0, 0};
  Vec3d angular_velocity{0, 0, 0};
  std::array<double, 4> orientation{1, 0, 0, 0};
  double radius = 0; // spheres; a shaped body's bounding radius comes from its shape
  int material = 0;
  int shape = 0;   // 0: sphere; k > 0: the k-th entry of the scene's shapes
  int source = -1; // index of the scene source that made it; -1: added by the program
  int tag = -1;    // index in Engine::tag_names(); -1: none
};

// Totals of the iterative narrow phases since the start of the run (or the restart).
struct NarrowPhaseTotals {
  std::int64_t evaluations = 0;
  std::int64_t iterations = 0;
  std::int64_t fallbacks = 0; // converged only through the fallback
  std::int64_t failures = 0;  // not converged: the pair had no contact that step
};

struct Diagnostics {
  std::int64_t step = 0;
  double time = 0;
  int particles = 0;
  double translational_energy = 0; // J
  double rotational_energy = 0;    // J
  double potential_energy = 0;     // J, gravity, relative to the origin
  int pair_contacts = 0;
  int wall_contacts = 0;
  double largest_overlap_ratio = 0; // overlap / radius, largest in the current step
  double discharged_mass = 0;       // kg, removed by outlets so far
  std::int64_t discharged_count = 0;
  double lost_mass = 0; // kg, removed on leaving the domain so far
  std::int64_t lost_count = 0;
  std::int64_t list_builds = 0;
  std::vector<std::int64_t> particles_per_source; // in the order of Engine::source_names()
  std::vector<std::int64_t> particles_per_tag;    // in the order of Engine::tag_names()
};

struct TimeStepAdvice {
  double rayleigh = 0;        // s, Rayleigh wave time of the smallest particle
  double hertz = 0;           // s, Hertz contact duration at the reference impact speed
  double suggested = 0;       // s, min(0.2 rayleigh, 0.1 hertz)
  double reference_speed = 0; // m/s
};

// A particle named in a failed check.
struct ParticleReport {
  std::int64_t id = 0;
  std::string shape; // "sphere", or the scene shape's name and family
  Vec3d position{0, 0, 0};
  Vec3d velocity{0, 0, 0};
};

// The outcome of Engine::check_health: healthy, or what went wrong, where, and why it may have.
struct HealthReport {
  std::string trigger;                   // empty: healthy; else non_finite, overlap, energy,
                                         // left_domain
  std::string finding;                   // what was measured, against which limit
  std::vector<ParticleReport> particles; // the first few involved
  std::vector<std::string> likely_causes;
  bool healthy() const { return trigger.empty(); }
};

class Engine {
public:
  // Builds materials, walls and outlets, and places the particles of every source that is not
  // inserted over time. Throws std::runtime_error with a readable message on impossible input.
  explicit Engine(const SceneConfig& scene);
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  int material_index(const std::string& name) const;
  void add_particles(const std::vector<ParticleInit>& particles);

  void step();
  void advance(std::int64_t steps);

  double time() const;
  std::int64_t step_count() const;
  int particle_count() const;
  int pair_candidates() const; // entries of the candidate pair list now
  int wall_candidates() const; // entries of the particle-wall candidate list now
  double time_step() const;
  TimeStepAdvice time_step_advice() const;

  Diagnostics diagnostics() const;
  // The checks of the scene's `checks` (docs/scene.md): non-finite state, overlap, kinetic
  // energy against its bound, particles outside the domain where the scene stops on them.
  HealthReport check_health() const;
  // Particles removed on leaving the domain so far, and the ids (at most 5) of the latest
  // removal that lost any.
  std::int64_t lost_count() const;
  std::vector<std::int64_t> latest_lost_ids() const;
  NarrowPhaseTotals narrow_phase_totals() const;
  int shape_id(const std::string& shape_name) const; // for add_particles
  ParticleSnapshot snapshot() const;
  // The scene's sources, and its distinct tags in the order the sources name them: what the
  // `source` and `tag` of a particle index.
  std::vector<std::string> source_names() const;
  std::vector<std::string> tag_names() const;
  std::vector<WallSurface> wall_surfaces() const;
  // Every pair and every particle-wall element touching at the last step, with its force; a
  // pair once, with the force on the particle listed first.
  std::vector<ContactForceRecord> contact_forces() const;

  // Test and benchmark knobs.
  void set_rebuild_every_step(bool every_step);
  double skin() const;

  void write_checkpoint(const std::string& path) const;
  void read_checkpoint(const std::string& path);

  static std::string backend_name();
  static int backend_concurrency();

private:
  struct State;
  std::unique_ptr<State> state_;
};

} // namespace kdem
