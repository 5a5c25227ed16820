// Superquadric narrow-phase benchmark: speed, convergence and accuracy of
// superquadric_pair_contact on named case sets, evaluated inside Kokkos::parallel_for.
//
//   kdem_bench_narrow_phase_<backend> --out FILE.json [--mode hard|sweep|failures]
//       [--tolerance T] [--max-iterations K] [--no-fallback] [--ellipsoid-general-newton]
//       [--repeat R] [--random-pairs N] [--sequences S] [--poses P] [--min-evaluations E]
//       [--failure-pairs F] [--seed SEED] [--lanes] [--kokkos-threads=T]
//
// hard:     the hard cases, random pairs and moving pairs (warm and cold) at one setting
//           (the defaults of NarrowPhaseControls unless given).
// sweep:    random and moving pairs for tolerance in {1e-4 ... 1e-12} x cap in {5, 10, 20, 40}
//           with the fallback, and the default setting without it.
// failures: F random pairs and F moving poses at one setting, in chunks; statuses only.
// --lanes:  each pair solved as the host engine solves it (shapes/superquadric_lanes.hpp): in
//           lanes (the pair in all four, as lanes do not depend on each other), by the scalar
//           solve where the lanes hand it back. Host builds only.
//
// Time per evaluation: median over R repetitions of (fenced Kokkos::Timer time of as many
// launches over the set as give at least E evaluations) / evaluations; a set smaller than E is
// timed as copies of itself in one launch. Also the process CPU time (all threads) per
// evaluation, which other processes on the cores disturb less. Errors are against a
// reference from the same solver with tolerance 1e-14 (1e-13, 1e-12 where that does not
// converge) and a cap of 200, cold started; the overlap error is relative to the reference
// overlap, and 1 for a contact missed or found where the reference has none. The chord bound: the
// midway overlap along the normal n cannot exceed the projected overlap h_j(n) + h_i(-n) from the
// exact support functions; the largest excess is reported.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <time.h>
#include <vector>

#include "kernels/types.hpp"
#include "perf/narrow_phase_cases.hpp"
#include "shapes/superquadric_lanes.hpp"
#include "src/build_info.hpp"

namespace {

using namespace kdem;
using namespace kdem::narrow_phase_bench;

struct Options {
  std::string mode = "hard";
  std::string out;
  NarrowPhaseControls controls;
  int repeat = 5;
  int random_pairs = 20000;
  int sequences = 200;
  int poses = 100;
  long long min_evaluations = 20000;
  long long failure_pairs = 1000000;
  std::uint64_t seed = 1;
  bool lanes = false;
  double load_at_start = -1; // set when the run starts
};

const char* usage =
    "usage: kdem_bench_narrow_phase_<backend> --out FILE.json [--mode hard|sweep|failures]\n"
    "    [--tolerance T] [--max-iterations K] [--no-fallback] [--ellipsoid-general-newton]\n"
    "    [--repeat R] [--random-pairs N] [--sequences S] [--poses P] [--min-evaluations E]\n"
    "    [--failure-pairs F] [--seed SEED] [--lanes]\n"
    "Kokkos options (e.g. --kokkos-threads=2) are passed to Kokkos.\n";

using OptionSetter = std::function<void(Options&, const std::string&)>;

// Options that take a value, by name.
const std::map<std::string, OptionSetter>& value_options() {
  static const std::map<std::string, OptionSetter> table = {
      {"--mode", [](Options& o, const std::string& v) { o.mode = v; }},
      {"--out", [](Options& o, const std::string& v) { o.out = v; }},
      {"--tolerance",
       [](Options& o, const std::string& v) { o.controls.tolerance = std::stod(v); }},
      {"--max-iterations",
       [](Options& o, const std::string& v) { o.controls.max_iterations = std::stoi(v); }},
      {"--repeat", [](Options& o, const std::string& v) { o.repeat = std::stoi(v); }},
      {"--random-pairs", [](Options& o, const std::string& v) { o.random_pairs = std::stoi(v); }},
      {"--sequences", [](Options& o, const std::string& v) { o.sequences = std::stoi(v); }},
      {"--poses", [](Options& o, const std::string& v) { o.poses = std::stoi(v); }},
      {"--min-evaluations",
       [](Options& o, const std::string& v) { o.min_evaluations = std::stoll(v); }},
      {"--failure-pairs",
       [](Options& o, const std::string& v) { o.failure_pairs = std::stoll(v); }},
      {"--seed", [](Options& o, const std::string& v) { o.seed = std::stoull(v); }}};
  return table;
}

void check(const Options& o) {
  if (o.mode != "hard" && o.mode != "sweep" && o.mode != "failures")
    throw std::runtime_error("--mode must be hard, sweep or failures");
  if (o.repeat < 1 || o.random_pairs < 1 || o.sequences < 1 || o.poses < 2)
    throw std::runtime_error("--repeat, --random-pairs, --sequences >= 1, --poses >= 2");
}

// Arguments starting with --kokkos are left to Kokkos.
Options parse(int argc, char** argv) {
  Options o;
  int k = 1;
  while (k < argc) {
    const std::string name = argv[k++];
    if (name.rfind("--kokkos", 0) == 0)
      continue;
    if (name == "--no-fallback") {
      o.controls.use_fallback = false;
      continue;
    }
    if (name == "--ellipsoid-general-newton") {
      o.controls.ellipsoid_scalar_root = false;
      continue;
    }
    if (name == "--lanes") {
      if (!KDEM_HOST_LANES)
        throw std::runtime_error("--lanes: this build has no host lanes");
      o.lanes = true;
      continue;
    }
    if (name == "-h" || name == "--help") {
      std::fputs(usage, stdout);
      std::exit(0);
    }
    const auto setter = value_options().find(name);
    if (setter == value_options().end())
      throw std::runtime_error("unknown argument '" + name + "'");
    if (k >= argc)
      throw std::runtime_error(name + " needs a value");
    setter->second(o, argv[k++]);
  }
  check(o);
  return o;
}

// ------------------------------------------------------------------ device evaluation

struct Outcome {
  double overlap = 0;
  Vec3 normal;
  int iterations = 0;
  int status = 0;
  int touching = 0;
  double tolerance = 0; // reference runs only: the tolerance it converged to
};

struct DeviceSet {
  Kokkos::View<PosePair*, MemSpace> pairs;
  int sequences = 0, poses = 1;
  bool warm_start = false;
  long long evaluations() const { return (long long)sequences * poses; }
};

DeviceSet upload(const CaseSet& set) {
  DeviceSet d;
  d.sequences = set.sequences;
  d.poses = set.poses;
  d.warm_start = set.warm_start;
  d.pairs = Kokkos::View<PosePair*, MemSpace>("narrow_phase_pairs", set.pairs.size());
  auto host = Kokkos::create_mirror_view(d.pairs);
  for (std::size_t k = 0; k < set.pairs.size(); ++k)
    host(k) = set.pairs[k];
  Kokkos::deep_copy(d.pairs, host);
  return d;
}

KOKKOS_INLINE_FUNCTION Outcome outcome_of(const NarrowPhaseResult& r) {
  Outcome o;
  o.overlap = r.geometry.overlap;
  o.normal = r.geometry.normal;
  o.iterations = r.iterations;
  o.status = r.status;
  o.touching = r.geometry.touching;
  return o;
}

// One pass over the set: sequences in parallel, the poses of a sequence in order, each pose
// solved by solve(pair, start) from the last pose's state when the set is warm-started.
template <class Solve>
void evaluate_sequences(const char* label, const DeviceSet& set, const Solve& solve,
                        Kokkos::View<Outcome*, MemSpace> outcomes) {
  const auto pairs = set.pairs;
  const int poses = set.poses;
  const bool warm = set.warm_start;
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(0, set.sequences), KOKKOS_LAMBDA(int s) {
        MidwayState state;
        for (int p = 0; p < poses; ++p) {
          const int k = s * poses + p;
          const NarrowPhaseResult r = solve(pairs(k), warm ? state : MidwayState{});
          outcomes(k) = outcome_of(r);
          state = r.status == 2 ? MidwayState{} : r.state;
        }
      });
}

struct ScalarSolve {
  NarrowPhaseControls controls;
  KOKKOS_INLINE_FUNCTION NarrowPhaseResult operator()(const PosePair& pair,
                                                      const MidwayState& start) const {
    return superquadric_pair_contact(pair.i, pair.j, start, controls);
  }
};

#if KDEM_HOST_LANES
// As the host engine: in lanes, by the scalar solve where they hand the pair back.
struct LaneSolve {
  NarrowPhaseControls controls;
  NarrowPhaseResult operator()(const PosePair& pair, const MidwayState& start) const {
    lanes::PairInputs in;
    for (int l = 0; l < lanes::width; ++l)
      lanes::set_lane(in, l, pair.i, pair.j, start);
    NarrowPhaseResult results[lanes::width];
    if (lanes::superquadric_pair_contact(pair.i.shape, pair.j.shape, in, controls, results) & 1)
      return results[0];
    return superquadric_pair_contact(pair.i, pair.j, start, controls);
  }
};
#endif

void evaluate(const DeviceSet& set, const NarrowPhaseControls& controls,
              Kokkos::View<Outcome*, MemSpace> outcomes, bool in_lanes = false) {
#if KDEM_HOST_LANES
  if (in_lanes)
    return evaluate_sequences("narrow_phase_bench_lanes", set, LaneSolve{controls}, outcomes);
#endif
  evaluate_sequences("narrow_phase_bench", set, ScalarSolve{controls}, outcomes);
}

// Cold-started solves at 1e-14, retried at 1e-13 and 1e-12 where they do not converge; always
// the general Newton (also for ellipsoids), so that the scalar root is checked against it.
void evaluate_reference(const DeviceSet& set, Kokkos::View<Outcome*, MemSpace> outcomes) {
  const auto pairs = set.pairs;
  Kokkos::parallel_for(
      "narrow_phase_reference", Kokkos::RangePolicy<ExecSpace>(0, set.evaluations()),
      KOKKOS_LAMBDA(int k) {
        NarrowPhaseControls controls;
        controls.max_iterations = 200;
        controls.max_homotopy_solves = 64;
        controls.ellipsoid_scalar_root = false;
        for (double tolerance = 1e-14; tolerance < 2e-12; tolerance *= 10) {
          controls.tolerance = tolerance;
          outcomes(k) = outcome_of(
              superquadric_pair_contact(pairs(k).i, pairs(k).j, MidwayState{}, controls));
          outcomes(k).tolerance = tolerance;
          if (outcomes(k).status != 2)
            break;
        }
      });
}

std::vector<Outcome> to_host(Kokkos::View<Outcome*, MemSpace> outcomes) {
  auto host = Kokkos::create_mirror_view(outcomes);
  Kokkos::deep_copy(host, outcomes);
  return std::vector<Outcome>(host.data(), host.data() + host.extent(0));
}

struct Measurement {
  std::vector<Outcome> outcomes;
  std::vector<double> seconds_per_evaluation;     // wall time, one per repetition
  std::vector<double> cpu_seconds_per_evaluation; // this process's CPU time, all threads
};

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

Measurement measure(const DeviceSet& set, const NarrowPhaseControls& controls, int repeat,
                    long long min_evaluations, bool in_lanes) {
  Kokkos::View<Outcome*, MemSpace> outcomes("narrow_phase_outcomes", set.evaluations());
  const long long launches =
      std::max(1LL, (min_evaluations + set.evaluations() - 1) / set.evaluations());
  evaluate(set, controls, outcomes, in_lanes); // untimed: first touch, page faults
  Measurement m;
  for (int r = 0; r < repeat; ++r) {
    Kokkos::fence();
    const double cpu_start = process_cpu_seconds();
    Kokkos::Timer timer;
    for (long long l = 0; l < launches; ++l)
      evaluate(set, controls, outcomes, in_lanes);
    Kokkos::fence();
    const double evaluations = double(launches * set.evaluations());
    m.seconds_per_evaluation.push_back(timer.seconds() / evaluations);
    m.cpu_seconds_per_evaluation.push_back((process_cpu_seconds() - cpu_start) / evaluations);
  }
  m.outcomes = to_host(outcomes);
  return m;
}

std::vector<Outcome> reference_outcomes(const DeviceSet& set) {
  Kokkos::View<Outcome*, MemSpace> outcomes("narrow_phase_reference", set.evaluations());
  evaluate_reference(set, outcomes);
  return to_host(outcomes);
}

// ------------------------------------------------------------------ statistics

// Middle element, or the mean of the two middle ones.
double median(std::vector<double> v) {
  if (v.empty())
    return 0;
  const auto middle = v.begin() + v.size() / 2;
  std::nth_element(v.begin(), middle, v.end());
  if (v.size() % 2 == 1)
    return *middle;
  return 0.5 * (*middle + *std::max_element(v.begin(), middle));
}

struct Spread {
  long long count = 0;
  double median = 0, p99 = 0, max = 0;
};

Spread spread_of(std::vector<double> v) {
  Spread s;
  s.count = (long long)v.size();
  if (v.empty())
    return s;
  std::sort(v.begin(), v.end());
  s.median = median(v);
  const std::size_t rank = std::size_t(std::ceil(0.99 * double(v.size()))); // nearest rank
  s.p99 = v[std::max<std::size_t>(rank, 1) - 1];
  s.max = v.back();
  return s;
}

double angle_between(Vec3 a, Vec3 b) {
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

struct Convergence {
  std::map<int, long long> histogram; // iterations -> evaluations
  long long evaluations = 0, fallbacks = 0, failures = 0, touching = 0, iterations = 0;
};

void add_outcomes(Convergence& c, const std::vector<Outcome>& outcomes) {
  for (const Outcome& o : outcomes) {
    ++c.histogram[o.iterations];
    ++c.evaluations;
    c.fallbacks += o.status == 1;
    c.failures += o.status == 2;
    c.touching += o.status != 2 && o.touching;
    c.iterations += o.iterations;
  }
}

Convergence convergence_of(const std::vector<Outcome>& outcomes) {
  Convergence c;
  add_outcomes(c, outcomes);
  return c;
}

struct Accuracy {
  Spread overlap_error, normal_error;
  long long touching_mismatches = 0; // converged, but touching where the reference is not or
                                     // the other way round; counted as overlap error 1
  long long reference_failures = 0;
  double loosest_reference_tolerance = 0;
  double worst_chord_excess = -1e300; // (overlap - projected overlap along the normal) / size
};

Accuracy accuracy_of(const CaseSet& set, const std::vector<Outcome>& outcomes,
                     const std::vector<Outcome>& reference) {
  Accuracy a;
  std::vector<double> overlap_errors, normal_errors;
  for (std::size_t k = 0; k < outcomes.size(); ++k) {
    const Outcome &o = outcomes[k], &ref = reference[k];
    a.reference_failures += ref.status == 2;
    a.loosest_reference_tolerance = std::max(a.loosest_reference_tolerance, ref.tolerance);
    if (o.status == 2 || ref.status == 2)
      continue;
    if (o.touching != ref.touching) {
      ++a.touching_mismatches;
      overlap_errors.push_back(1.0); // a missed or spurious contact: the whole overlap is wrong
      continue;
    }
    if (!o.touching)
      continue;
    overlap_errors.push_back(std::fabs(o.overlap - ref.overlap) / ref.overlap);
    normal_errors.push_back(angle_between(o.normal, ref.normal));
    const PosePair& pair = set.pairs[k];
    const double excess = o.overlap - projected_overlap(pair.i, pair.j, o.normal);
    a.worst_chord_excess = std::max(a.worst_chord_excess, excess / pair_size(pair.i, pair.j));
  }
  a.overlap_error = spread_of(overlap_errors);
  a.normal_error = spread_of(normal_errors);
  return a;
}

// ------------------------------------------------------------------ JSON

std::string number(double x) {
  std::ostringstream text;
  text << std::setprecision(6) << x;
  return std::isfinite(x) ? text.str() : "null";
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s)
    out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return out + "\"";
}

std::string spread_json(const Spread& s) {
  return "{\"count\": " + std::to_string(s.count) + ", \"median\": " + number(s.median) +
         ", \"p99\": " + number(s.p99) + ", \"max\": " + number(s.max) + "}";
}

std::string histogram_json(const std::map<int, long long>& histogram) {
  std::string iterations, counts;
  for (const auto& [k, count] : histogram) {
    iterations += (iterations.empty() ? "" : ", ") + std::to_string(k);
    counts += (counts.empty() ? "" : ", ") + std::to_string(count);
  }
  return "{\"iterations\": [" + iterations + "], \"counts\": [" + counts + "]}";
}

std::string controls_json(const NarrowPhaseControls& c) {
  return "{\"tolerance\": " + number(c.tolerance) +
         ", \"max_iterations\": " + std::to_string(c.max_iterations) +
         ", \"use_fallback\": " + (c.use_fallback ? "true" : "false") +
         ", \"homotopy_stages\": " + std::to_string(c.homotopy_stages) +
         ", \"max_homotopy_solves\": " + std::to_string(c.max_homotopy_solves) +
         ", \"ellipsoid_scalar_root\": " + (c.ellipsoid_scalar_root ? "true" : "false") + "}";
}

std::string convergence_json(const Convergence& c) {
  const double evaluations = double(std::max(1LL, c.evaluations));
  std::ostringstream j;
  j << "\"evaluations\": " << c.evaluations << ", \"touching\": " << c.touching
    << ", \"fallbacks\": " << c.fallbacks << ", \"failures\": " << c.failures
    << ", \"failure_fraction\": " << number(double(c.failures) / evaluations)
    << ", \"mean_iterations\": " << number(double(c.iterations) / evaluations)
    << ", \"iteration_histogram\": " << histogram_json(c.histogram);
  return j.str();
}

std::string nanoseconds_json(const std::vector<double>& seconds) {
  std::string out = "[";
  for (std::size_t r = 0; r < seconds.size(); ++r)
    out += (r ? ", " : "") + number(1e9 * seconds[r]);
  return out + "]";
}

std::string set_json(const CaseSet& set, const Measurement& m, const std::vector<Outcome>& ref) {
  const Accuracy a = accuracy_of(set, m.outcomes, ref);
  std::ostringstream j;
  j << "{\"name\": " << quoted(set.name) << ", \"sequences\": " << set.sequences
    << ", \"poses\": " << set.poses << ", \"warm_start\": " << (set.warm_start ? "true" : "false")
    << ", " << convergence_json(convergence_of(m.outcomes))
    << ", \"ns_per_evaluation\": " << number(1e9 * median(m.seconds_per_evaluation))
    << ", \"ns_per_evaluation_repetitions\": " << nanoseconds_json(m.seconds_per_evaluation)
    << ", \"cpu_ns_per_evaluation\": " << number(1e9 * median(m.cpu_seconds_per_evaluation))
    << ", \"cpu_ns_per_evaluation_repetitions\": " << nanoseconds_json(m.cpu_seconds_per_evaluation)
    << ", \"overlap_error\": " << spread_json(a.overlap_error)
    << ", \"normal_error_rad\": " << spread_json(a.normal_error)
    << ", \"touching_mismatches\": " << a.touching_mismatches
    << ", \"reference_failures\": " << a.reference_failures
    << ", \"loosest_reference_tolerance\": " << number(a.loosest_reference_tolerance)
    << ", \"worst_chord_excess\": " << number(a.worst_chord_excess) << "}";
  return j.str();
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
      return line.substr(line.find(':') + 2);
  return "unknown";
}

// The 1-minute load average: other processes competing for the cores.
double load_average() {
  std::ifstream in("/proc/loadavg");
  double load = -1;
  in >> load;
  return load;
}

std::string header_json(const Options& o) {
  std::ostringstream j;
  j << "\"benchmark\": \"narrow_phase\", \"mode\": " << quoted(o.mode)
    << ", \"backend\": " << quoted(ExecSpace::name())
    << ", \"threads\": " << ExecSpace().concurrency() << ", \"cpu_model\": " << quoted(cpu_model())
    << ", \"hardware_threads\": " << std::thread::hardware_concurrency()
    << ", \"repeat\": " << o.repeat << ", \"min_evaluations\": " << o.min_evaluations
    << ", \"seed\": " << o.seed << ", \"lanes\": " << (o.lanes ? "true" : "false")
    << ", \"load_average_start\": " << number(o.load_at_start)
    << ", \"load_average_end\": " << number(load_average()) << ", \"git\": \"" << kdem::git_hash()
    << "\"";
  return j.str();
}

void write_json(const std::string& path, const std::string& json) {
  std::cout << json << std::endl;
  if (path.empty())
    return;
  const std::filesystem::path target(path);
  if (target.has_parent_path())
    std::filesystem::create_directories(target.parent_path());
  std::ofstream out(target);
  out << json << '\n';
  if (!out)
    throw std::runtime_error("cannot write " + path);
}

// ------------------------------------------------------------------ modes

// A small set is timed as copies of itself in one launch, so that the launch overhead and the
// load imbalance of a few long solves do not dominate the time per evaluation.
CaseSet replicated(const CaseSet& set, long long min_evaluations) {
  const long long copies = std::max(1LL, min_evaluations / (long long)set.pairs.size());
  CaseSet timing = set;
  timing.sequences = int(copies * set.sequences);
  timing.pairs.clear();
  for (long long c = 0; c < copies; ++c)
    timing.pairs.insert(timing.pairs.end(), set.pairs.begin(), set.pairs.end());
  return timing;
}

struct PreparedSet {
  CaseSet cases;
  DeviceSet device; // the set itself: outcomes and the reference
  DeviceSet timing; // the set replicated to at least min_evaluations
  std::vector<Outcome> reference;
};

PreparedSet prepare(CaseSet cases, long long min_evaluations) {
  PreparedSet p{std::move(cases), {}, {}, {}};
  p.device = upload(p.cases);
  p.timing = (long long)p.cases.pairs.size() < min_evaluations
                 ? upload(replicated(p.cases, min_evaluations))
                 : p.device;
  p.reference = reference_outcomes(p.device);
  std::fprintf(stderr, "[bench] %s: %zu pairs, reference done\n", p.cases.name.c_str(),
               p.cases.pairs.size());
  return p;
}

std::string run_json(const NarrowPhaseControls& controls, const std::vector<PreparedSet>& sets,
                     const Options& o) {
  std::string json = "{\"controls\": " + controls_json(controls) + ", \"sets\": [";
  for (std::size_t k = 0; k < sets.size(); ++k) {
    Measurement m = measure(sets[k].timing, controls, o.repeat, o.min_evaluations, o.lanes);
    m.outcomes.resize(sets[k].cases.pairs.size()); // the first copy is the set itself
    json += (k ? ",\n    " : "\n    ") + set_json(sets[k].cases, m, sets[k].reference);
  }
  return json + "]}";
}

std::vector<PreparedSet> random_and_moving(const Options& o, bool with_cold) {
  std::vector<PreparedSet> sets;
  sets.push_back(prepare(random_set(o.random_pairs, o.seed), o.min_evaluations));
  sets.push_back(prepare(moving_set(o.sequences, o.poses, o.seed + 1, true), o.min_evaluations));
  if (with_cold)
    sets.push_back(prepare(moving_set(o.sequences, o.poses, o.seed + 1, false), o.min_evaluations));
  return sets;
}

std::string hard_mode(const Options& o) {
  std::vector<PreparedSet> sets;
  for (CaseSet& c : hard_case_sets(o.seed + 2))
    sets.push_back(prepare(std::move(c), o.min_evaluations));
  for (PreparedSet& p : random_and_moving(o, true))
    sets.push_back(std::move(p));
  return "{" + header_json(o) + ",\n  \"runs\": [" + run_json(o.controls, sets, o) + "]}";
}

std::string sweep_mode(const Options& o) {
  const std::vector<PreparedSet> sets = random_and_moving(o, false);
  std::string runs;
  const auto add = [&](const NarrowPhaseControls& c) {
    std::fprintf(stderr, "[bench] tolerance %g, cap %d, fallback %d\n", c.tolerance,
                 c.max_iterations, int(c.use_fallback));
    runs += (runs.empty() ? "\n  " : ",\n  ") + run_json(c, sets, o);
  };
  for (double tolerance : {1e-4, 1e-6, 1e-8, 1e-10, 1e-12})
    for (int cap : {5, 10, 20, 40}) {
      NarrowPhaseControls c;
      c.tolerance = tolerance;
      c.max_iterations = cap;
      add(c);
    }
  NarrowPhaseControls plain;
  plain.use_fallback = false;
  add(plain);
  return "{" + header_json(o) + ",\n  \"runs\": [" + runs + "]}";
}

// Statuses of many fresh pairs, generated and evaluated a chunk at a time (no reference).
std::string failure_set_json(const std::string& name, long long total, const Options& o,
                             CaseSet (*chunk_of)(int, std::uint64_t, const Options&)) {
  const int chunk_size = 50000;
  Convergence convergence;
  for (std::uint64_t chunk = 0; convergence.evaluations < total; ++chunk) {
    const DeviceSet device = upload(chunk_of(chunk_size, o.seed + 1000 + chunk, o));
    Kokkos::View<Outcome*, MemSpace> outcomes("narrow_phase_outcomes", device.evaluations());
    evaluate(device, o.controls, outcomes, o.lanes);
    add_outcomes(convergence, to_host(outcomes));
  }
  return "{\"name\": " + quoted(name) + ", " + convergence_json(convergence) + "}";
}

CaseSet random_chunk(int size, std::uint64_t seed, const Options&) {
  return random_set(size, seed);
}

CaseSet moving_chunk(int size, std::uint64_t seed, const Options& o) {
  return moving_set(std::max(1, size / o.poses), o.poses, seed, true);
}

std::string failures_mode(const Options& o) {
  return "{" + header_json(o) + ", \"controls\": " + controls_json(o.controls) +
         ",\n  \"sets\": [" + failure_set_json("random", o.failure_pairs, o, random_chunk) +
         ",\n    " + failure_set_json("moving", o.failure_pairs, o, moving_chunk) + "]}";
}

int run(Options o) {
  o.load_at_start = load_average();
  const std::string json =
      o.mode == "hard" ? hard_mode(o) : (o.mode == "sweep" ? sweep_mode(o) : failures_mode(o));
  write_json(o.out, json);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  std::string stage = "arguments";
  try {
    const Options options = parse(argc, argv);
    stage = "run";
    Kokkos::ScopeGuard kokkos(argc, argv);
    kdem::install_memory_space_check<kdem::MemSpace>();
    return run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kdem_bench_narrow_phase (%s): %s\n", stage.c_str(), e.what());
    if (stage == "arguments")
      std::fputs(usage, stderr);
    return stage == "arguments" ? 2 : 1;
  }
}
