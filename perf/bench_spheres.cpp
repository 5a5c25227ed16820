// Throughput benchmark: a settled bed of N particles in a box under gravity, Hertz-Mindlin with
// tangential history and Coulomb friction, no rolling resistance. --shape picks the particles:
// spheres (r = 1 mm +- 10 %, the default), or superquadrics of the volume of a 1 mm sphere:
// ellipsoids (a = b, c = 2a), cylinders (n1 = 8, n2 = 2, a = b = c) or cubes (n1 = n2 = 8).
//
//   kdem_bench_openmp --n N --steps M --repeat R [--warmup W] [--out FILE.json]
//                     [--shape sphere|ellipsoid|cylinder|cube|poly_ellipsoid|poly_cube|pebble|
//                              clump_K]
//                     [--cache-dir DIR]
//                     [--write-data FILE.data] [--rebuild-every-step] [--unsorted]
//                     [--mesh-walls TRIANGLES] [--kokkos-threads=T]
//
// --unsorted gives the engine the particles in a shuffled order and switches its sort by cell
// off (scene key sort_by_cell), for measuring what the sort gains.
//
// --mesh-walls T gives the bed, instead of the box's five planes, a mesh wall: the same open box
// triangulated into about T triangles (each face cut into squares of one size, each square into
// two triangles; at least ten triangles), written as binary STL into --cache-dir. For measuring
// the wall broad phase against the mesh's size.
//
// After the timed repeats, one more run of M steps with every kernel fenced and timed by label
// gives the time per kernel (`kernels` in the JSON), and the bytes the engine allocated in its
// memory space are counted from its construction on (`memory`).
//
// The bed is built from one settled tile of 1000 particles (20 mm x 20 mm footprint, about ten
// diameters deep), settled once with this engine and cached as text in --cache-dir. N spheres
// are laid out as kx x ky copies of the tile, every other copy mirrored, so that two copies meet
// face to face exactly as the tile met its side wall: the composite is in equilibrium from the
// start. When N is not a product of the tile count that lays out near-square, the topmost
// spheres are left out. Every run starts from these positions at rest, runs W untimed warm-up
// steps (contact history builds up), then R timed runs of M steps. Only engine.advance is timed.
//
// --write-data writes the same bed as a LIGGGHTS/LAMMPS data file (atom_style granular) so that
// perf/run_bench.py can run the peer code on identical positions.
#include <Kokkos_Core.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/types.hpp"
#include "shapes/clump_properties.hpp"
#include "shapes/poly_superquadric_properties.hpp"
#include "shapes/superquadric_properties.hpp"
#include "src/build_info.hpp"
#include "src/clump_scene.hpp"
#include "src/engine.hpp"
#include "src/kernel_timer.hpp"
#include "src/poly_superquadric_scene.hpp"
#include "src/scene.hpp"
#include "src/superquadric_scene.hpp"

namespace {

namespace fs = std::filesystem;

// The benchmark's material and numerics; perf/run_bench.py writes the same into the LIGGGHTS
// input (it reads them back from the JSON record).
struct BenchParameters {
  double density = 2500;      // kg/m^3
  double youngs = 1e8;        // Pa
  double poisson = 0.3;       // -
  double restitution = 0.5;   // -
  double friction = 0.5;      // -
  double mean_radius = 1e-3;  // m
  double radius_spread = 0.1; // radii uniform in mean (1 +- spread)
  double time_step = 4e-6;    // s, 0.16 of the Rayleigh time of the smallest sphere
  double skin = 2e-4;         // m, 0.1 mean diameter
  double gravity = 9.81;      // m/s^2, along -z
  double tile_size = 0.02;    // m, square footprint of one tile
  int tile_count = 1000;      // spheres per tile
  std::uint64_t seed = 1;
};

// A benchmark particle shape of the volume of a sphere of mean_radius: a superquadric with
// c = aspect x a (a = b), or a poly-superquadric with extents plus and minus (in units of a
// common scale); "sphere" is the polydisperse sphere bed. poly_ellipsoid and poly_cube are the
// ellipsoid and the cube as poly-superquadrics (r+ = r-): the same bodies, for the cost of the
// poly-superquadric path; pebble is the book's (Sect. 3.3.3: r+/r- = 0.7, 0.4, 0.5). clump_K
// (K = 1 to 8) is a clump of K equal spheres whose centres lie half a radius from the clump's
// centre at the vertices of a compact polyhedron (a point, a segment, a triangle, a tetrahedron,
// a triangular bipyramid, an octahedron, a pentagonal bipyramid, a cube): nearly round whatever
// K, so that its cost measures the element count.
struct BenchShape {
  std::string name = "sphere";
  double aspect = 1, n1 = 2, n2 = 2;
  bool poly = false;
  kdem::Vec3 plus{1, 1, 1}, minus{1, 1, 1};
  int clump_elements = 0;
  bool is_sphere() const { return name == "sphere"; }
  // Whether the body is its own mirror image in each plane of its body axes, so that a mirrored
  // copy of a settled tile is the same bed reflected (make_bed); otherwise copies are translated.
  bool mirror_symmetric() const {
    if (clump_elements > 0)
      return clump_elements == 1 || clump_elements == 2 || clump_elements == 6 ||
             clump_elements == 8;
    return !poly || (plus.x == minus.x && plus.y == minus.y && plus.z == minus.z);
  }
};

// Directions of the element centres of clump_K.
std::vector<kdem::Vec3> clump_directions(int k) {
  const double s3 = 1 / std::sqrt(3.0);
  const auto ring = [](int n, double z) {
    std::vector<kdem::Vec3> v;
    for (int m = 0; m < n; ++m)
      v.push_back({std::cos(2 * M_PI * m / n), std::sin(2 * M_PI * m / n), z});
    return v;
  };
  std::vector<kdem::Vec3> d;
  switch (k) {
  case 1:
    return {{0, 0, 0}};
  case 2:
    return {{1, 0, 0}, {-1, 0, 0}};
  case 3:
    return ring(3, 0);
  case 4:
    return {{s3, s3, s3}, {s3, -s3, -s3}, {-s3, s3, -s3}, {-s3, -s3, s3}};
  case 5:
  case 7:
    d = ring(k - 2, 0);
    d.push_back({0, 0, 1});
    d.push_back({0, 0, -1});
    return d;
  case 6:
    return {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  case 8:
    for (int m = 0; m < 8; ++m)
      d.push_back({m & 1 ? s3 : -s3, m & 2 ? s3 : -s3, m & 4 ? s3 : -s3});
    return d;
  default:
    throw std::runtime_error("clump_K takes K from 1 to 8");
  }
}

// clump_K's elements at unit element radius (before the scaling to the bed's volume).
std::vector<kdem::ClumpElement> unit_clump(int k) {
  std::vector<kdem::ClumpElement> elements;
  for (const kdem::Vec3 d : clump_directions(k))
    elements.push_back({kdem::make_superquadric(1, 1, 1, 2, 2), 0.5 * d, kdem::Quat{1, 0, 0, 0}});
  return elements;
}

BenchShape bench_shape(const std::string& name) {
  if (name == "sphere")
    return {};
  if (name == "ellipsoid")
    return {name, 2, 2, 2};
  if (name == "cylinder")
    return {name, 1, 8, 2};
  if (name == "cube")
    return {name, 1, 8, 8};
  if (name == "poly_ellipsoid")
    return {name, 1, 2, 2, true, {1, 1, 2}, {1, 1, 2}};
  if (name == "poly_cube")
    return {name, 1, 8, 8, true, {1, 1, 1}, {1, 1, 1}};
  if (name == "pebble")
    return {name, 1, 2, 2, true, {0.7, 0.4, 0.5}, {1, 1, 1}};
  if (name.size() == 7 && name.compare(0, 6, "clump_") == 0 && name[6] >= '1' && name[6] <= '8') {
    BenchShape clump{name};
    clump.clump_elements = name[6] - '0';
    return clump;
  }
  throw std::runtime_error("--shape must be sphere, ellipsoid, cylinder, cube, poly_ellipsoid, "
                           "poly_cube, pebble or clump_K (K = 1 to 8), not '" +
                           name + "'");
}

kdem::PolySuperquadricShape poly_shape_of(const BenchShape& shape, double scale) {
  return kdem::make_poly_superquadric(scale * shape.plus, scale * shape.minus, shape.n1, shape.n2);
}

// The scale of the shape with the volume of a sphere of radius r.
double scale_of(const BenchShape& shape, double r) {
  if (shape.clump_elements > 0)
    return std::cbrt(4.0 / 3.0 * M_PI * r * r * r /
                     kdem::clump_mass_properties(unit_clump(shape.clump_elements)).volume);
  const double unit = shape.poly
                          ? kdem::poly_superquadric_mass_properties(poly_shape_of(shape, 1)).volume
                          : kdem::superquadric_volume(
                                kdem::make_superquadric(1, 1, shape.aspect, shape.n1, shape.n2));
  return std::cbrt(4.0 / 3.0 * M_PI * r * r * r / unit);
}

// Semi-axes (a, a, aspect a) of the superquadric with the volume of a sphere of radius r.
kdem::Vec3d half_axes_of(const BenchShape& shape, double r) {
  const double a = scale_of(shape, r);
  return {a, a, shape.aspect * a};
}

kdem::ShapeConfig shape_config(const BenchShape& shape, double r) {
  if (shape.clump_elements > 0) {
    std::vector<kdem::ClumpElementParameters> elements;
    for (const kdem::ClumpElement& e : unit_clump(shape.clump_elements)) {
      kdem::ClumpElementParameters element;
      element.sphere = true;
      element.half_axes = {1e-3, 1e-3, 1e-3}; // scaled to the volume by equivalent_diameter
      element.position = {1e-3 * e.centre.x, 1e-3 * e.centre.y, 1e-3 * e.centre.z};
      elements.push_back(element);
    }
    return kdem::clump_shape_config(shape.name, elements, 2 * r);
  }
  if (!shape.poly)
    return kdem::superquadric_shape_config(shape.name, half_axes_of(shape, r), shape.n1, shape.n2);
  const double scale = scale_of(shape, r);
  const auto vec = [&](kdem::Vec3 v) { return kdem::Vec3d{scale * v.x, scale * v.y, scale * v.z}; };
  return kdem::poly_superquadric_shape_config(shape.name, vec(shape.plus), vec(shape.minus),
                                              shape.n1, shape.n2);
}

double bounding_radius_of(const BenchShape& shape, double r) {
  if (shape.clump_elements > 0) {
    const std::vector<kdem::ClumpElement> unit = unit_clump(shape.clump_elements);
    return scale_of(shape, r) *
           kdem::clump_bounding_radius(unit, kdem::clump_mass_properties(unit).centroid);
  }
  if (!shape.poly) {
    const kdem::Vec3d axes = half_axes_of(shape, r);
    return kdem::superquadric_bounding_radius(
        kdem::make_superquadric(axes[0], axes[1], axes[2], shape.n1, shape.n2));
  }
  const kdem::PolySuperquadricShape poly = poly_shape_of(shape, scale_of(shape, r));
  return kdem::poly_superquadric_bounding_radius(
      poly, kdem::poly_superquadric_mass_properties(poly).centroid);
}

// The smallest semi-axis (superquadric) or extent (poly-superquadric).
double smallest_length_of(const BenchShape& shape, double r) {
  if (shape.clump_elements > 0)
    return scale_of(shape, r); // the element radius
  if (shape.poly)
    return kdem::smallest_extent(poly_shape_of(shape, scale_of(shape, r)));
  const kdem::Vec3d axes = half_axes_of(shape, r);
  return std::min({axes[0], axes[1], axes[2]});
}

struct Options {
  long long n = 1000;
  long long steps = 1000;
  int repeat = 3;
  long long warmup = 1000;
  std::string out;
  std::string cache_dir = "perf/cache";
  std::string write_data;
  bool rebuild_every_step = false;
  bool unsorted = false;                 // particles in a shuffled order, never sorted by cell
  long long mesh_triangles = 0;          // > 0: the box as a mesh wall of about this many triangles
  bool ellipsoid_general_newton = false; // superquadric_contact.ellipsoid_scalar_root: false
  bool no_box_certificates = false;      // superquadric_contact.box_certificates: false
  BenchShape shape;
};

// One particle of a bed: centre, radius (spheres) and orientation (w, x, y, z).
struct Sphere {
  double x, y, z, r;
  double q[4] = {1, 0, 0, 0};
};

struct Bed {
  std::vector<Sphere> spheres;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}; // walls on x, y and z = lo[2]; hi[2] is the
                                               // top of the simulation domain (open)
  int tiles_x = 1, tiles_y = 1;
};

const char* usage =
    "usage: kdem_bench_<backend> --n N --steps M --repeat R [--warmup W] [--out FILE.json]\n"
    "                            [--shape "
    "sphere|ellipsoid|cylinder|cube|poly_ellipsoid|poly_cube|pebble|clump_K]\n"
    "                            [--cache-dir DIR]\n"
    "                            [--write-data FILE.data] [--rebuild-every-step] [--unsorted]\n"
    "                            [--mesh-walls TRIANGLES] [--ellipsoid-general-newton]\n"
    "                            [--no-box-certificates]\n"
    "Kokkos options (e.g. --kokkos-threads=2) are passed to Kokkos.\n";

Options parse(int argc, char** argv) {
  Options o;
  std::vector<std::string> words;
  for (int k = 1; k < argc; ++k)
    if (std::strncmp(argv[k], "--kokkos", 8) != 0)
      words.emplace_back(argv[k]);
  for (std::size_t k = 0; k < words.size(); ++k) {
    const std::string& w = words[k];
    auto value = [&]() -> std::string {
      if (k + 1 >= words.size())
        throw std::runtime_error(w + " needs a value");
      return words[++k];
    };
    if (w == "--n")
      o.n = std::stoll(value());
    else if (w == "--steps")
      o.steps = std::stoll(value());
    else if (w == "--repeat")
      o.repeat = std::stoi(value());
    else if (w == "--warmup")
      o.warmup = std::stoll(value());
    else if (w == "--out")
      o.out = value();
    else if (w == "--cache-dir")
      o.cache_dir = value();
    else if (w == "--write-data")
      o.write_data = value();
    else if (w == "--rebuild-every-step")
      o.rebuild_every_step = true;
    else if (w == "--shape")
      o.shape = bench_shape(value());
    else if (w == "--unsorted")
      o.unsorted = true;
    else if (w == "--mesh-walls")
      o.mesh_triangles = std::stoll(value());
    else if (w == "--ellipsoid-general-newton")
      o.ellipsoid_general_newton = true;
    else if (w == "--no-box-certificates")
      o.no_box_certificates = true;
    else if (w == "-h" || w == "--help") {
      std::fputs(usage, stdout);
      std::exit(0);
    } else
      throw std::runtime_error("unknown argument '" + w + "'");
  }
  if (o.n < 1 || o.steps < 0 || o.repeat < 0 || o.warmup < 0 || o.mesh_triangles < 0)
    throw std::runtime_error(
        "--n must be positive; --steps, --repeat, --warmup, --mesh-walls not negative");
  if (!o.write_data.empty() && !o.shape.is_sphere())
    throw std::runtime_error("--write-data writes sphere beds only (LIGGGHTS granular atoms)");
  return o;
}

kdem::MaterialConfig bench_material(const BenchParameters& p) {
  kdem::MaterialConfig m;
  m.name = "glass_like";
  m.density = p.density;
  m.youngs_modulus = p.youngs;
  m.poisson_ratio = p.poisson;
  m.restitution = p.restitution;
  m.friction = p.friction;
  m.rolling_friction = 0;
  return m;
}

kdem::WallConfig box_walls(const BenchParameters& p, const double lo[3], const double hi[3]) {
  kdem::WallConfig w;
  w.kind = kdem::WallConfig::Kind::Box;
  w.name = "box";
  w.material = bench_material(p).name;
  w.min = {lo[0], lo[1], lo[2]};
  w.max = {hi[0], hi[1], hi[2]};
  w.open_faces = {"zmax"};
  return w;
}

kdem::SceneConfig base_scene(const BenchParameters& p, const BenchShape& shape, const double lo[3],
                             const double hi[3]) {
  kdem::SceneConfig scene;
  if (!shape.is_sphere()) {
    scene.shapes = {shape_config(shape, p.mean_radius)};
  }
  scene.source_file = "bench_spheres";
  scene.gravity = {0, 0, -p.gravity};
  scene.time_step = p.time_step;
  scene.duration = 1e300;
  scene.skin = p.skin;
  scene.has_domain = true;
  scene.domain_min = {lo[0], lo[1], lo[2]};
  scene.domain_max = {hi[0], hi[1], hi[2]};
  scene.materials = {bench_material(p)};
  scene.walls = {box_walls(p, lo, hi)};
  return scene;
}

// One face of the open box: the plane x_axis = at, spanned by axes u and w over [lo, hi].
struct BoxFace {
  int axis, u, w;
  double at;
};

// Appends `face` cut into nu x nw squares, each as two triangles. Corners are computed from
// their integer indices with the ends exact, so that faces meeting at an edge share its vertices
// bit for bit (the mesh reader welds equal coordinates).
void add_face(std::vector<std::array<float, 9>>& triangles, const BoxFace& face, const double lo[3],
              const double hi[3], const int cuts[3]) {
  auto corner = [&](int i, int j) {
    double x[3];
    x[face.axis] = face.at;
    x[face.u] =
        i == cuts[face.u] ? hi[face.u] : lo[face.u] + (hi[face.u] - lo[face.u]) * i / cuts[face.u];
    x[face.w] =
        j == cuts[face.w] ? hi[face.w] : lo[face.w] + (hi[face.w] - lo[face.w]) * j / cuts[face.w];
    return std::array<float, 3>{float(x[0]), float(x[1]), float(x[2])};
  };
  for (int i = 0; i < cuts[face.u]; ++i)
    for (int j = 0; j < cuts[face.w]; ++j) {
      const auto a = corner(i, j), b = corner(i + 1, j), c = corner(i + 1, j + 1),
                 d = corner(i, j + 1);
      triangles.push_back({a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2]});
      triangles.push_back({a[0], a[1], a[2], c[0], c[1], c[2], d[0], d[1], d[2]});
    }
}

// The open box [lo, hi] (no top) as a binary STL of about `wanted` triangles in `dir`; returns
// its path and the number of triangles.
std::string write_mesh_box(const double lo[3], const double hi[3], long long wanted,
                           const std::string& dir, long long& count) {
  double extent[3], area = 0;
  for (int a = 0; a < 3; ++a)
    extent[a] = hi[a] - lo[a];
  area = extent[0] * extent[1] + 2 * extent[2] * (extent[0] + extent[1]);
  const double size = std::sqrt(2 * area / double(wanted));
  int cuts[3];
  for (int a = 0; a < 3; ++a)
    cuts[a] = std::max(1, int(std::lround(extent[a] / size)));
  std::vector<std::array<float, 9>> triangles;
  const BoxFace faces[5] = {
      {2, 0, 1, lo[2]}, {0, 1, 2, lo[0]}, {0, 1, 2, hi[0]}, {1, 0, 2, lo[1]}, {1, 0, 2, hi[1]}};
  for (const BoxFace& face : faces)
    add_face(triangles, face, lo, hi, cuts);
  count = (long long)triangles.size();
  std::ostringstream name;
  name << "mesh_box_" << cuts[0] << "x" << cuts[1] << "x" << cuts[2] << ".stl";
  const fs::path path = fs::path(dir) / name.str();
  fs::create_directories(path.parent_path());
  const std::string partial = path.string() + ".part";
  std::ofstream out(partial, std::ios::binary);
  const char header[80] = "kdem benchmark: open box";
  out.write(header, sizeof header);
  const std::uint32_t n = std::uint32_t(triangles.size());
  out.write(reinterpret_cast<const char*>(&n), sizeof n);
  for (const auto& t : triangles) {
    const float normal[3] = {0, 0, 0};
    const std::uint16_t attributes = 0;
    out.write(reinterpret_cast<const char*>(normal), sizeof normal);
    out.write(reinterpret_cast<const char*>(t.data()), sizeof(float) * 9);
    out.write(reinterpret_cast<const char*>(&attributes), sizeof attributes);
  }
  out.close();
  if (!out)
    throw std::runtime_error("cannot write " + partial);
  fs::rename(partial, path);
  return path.string();
}

std::string tile_cache_name(const BenchParameters& p, const BenchShape& shape) {
  std::ostringstream name;
  if (shape.is_sphere())
    name << "sphere_tile_v2";
  else
    name << shape.name << "_tile_v2_aspect" << shape.aspect << "_n" << shape.n1 << "_" << shape.n2;
  name << "_n" << p.tile_count << "_seed" << p.seed << "_E" << p.youngs << "_dt" << p.time_step
       << ".txt";
  return name.str();
}

// Pours the tile's particles from a loose random placement into a box and lets them settle.
// Superquadrics are placed by their bounding spheres, so they are poured from higher up: the
// region holds the bounding spheres at a solid fraction of 0.2.
std::vector<Sphere> settle_tile(const BenchParameters& p, const BenchShape& shape) {
  double pour_height = 0.05;
  if (!shape.is_sphere()) {
    const double bounding = bounding_radius_of(shape, p.mean_radius);
    const double placed = p.tile_count * 4.0 / 3.0 * M_PI * std::pow(bounding, 3);
    pour_height = std::max(pour_height, placed / 0.2 / (p.tile_size * p.tile_size));
  }
  const double domain_height = pour_height + 0.01;
  const double lo[3] = {0, 0, 0}, hi[3] = {p.tile_size, p.tile_size, domain_height};
  kdem::SceneConfig scene = base_scene(p, shape, lo, hi);
  kdem::ParticleSourceConfig source;
  source.name = "tile";
  source.material = scene.materials[0].name;
  source.sizes.kind = kdem::SizeDistributionConfig::Kind::Uniform;
  source.sizes.min_radius = p.mean_radius * (1 - p.radius_spread);
  source.sizes.max_radius = p.mean_radius * (1 + p.radius_spread);
  source.region.kind = kdem::RegionConfig::Kind::Box;
  source.region.min = {0, 0, 0};
  source.region.max = {p.tile_size, p.tile_size, pour_height};
  source.count = p.tile_count;
  source.seed = p.seed;
  if (!shape.is_sphere()) {
    source.shape = shape.name;
    source.random_orientation = true;
    source.sizes = kdem::SizeDistributionConfig{};
    source.sizes.kind = kdem::SizeDistributionConfig::Kind::Monodisperse;
    source.sizes.radius = smallest_length_of(shape, p.mean_radius);
  }
  scene.sources = {source};
  kdem::Engine engine(scene);

  const double mass = p.density * 4.0 / 3.0 * M_PI * std::pow(p.mean_radius, 3);
  const double energy_scale = p.tile_count * mass * p.gravity * p.mean_radius;
  const std::int64_t chunk = std::llround(0.01 / p.time_step);
  // Flat-faced superquadrics keep a jitter of their contact points: a tile of cylinders
  // (n1 = 8) still had 5e-6 to 1e-5 N m g r of kinetic energy between 1.9 and 2 s (measured),
  // so they count as settled at 2e-5 (a mean speed of 0.6 mm/s).
  const double settled_energy = (shape.is_sphere() ? 1e-6 : 2e-5) * energy_scale;
  for (int k = 1;; ++k) {
    engine.advance(chunk);
    const kdem::Diagnostics d = engine.diagnostics();
    // Settled by the translational energy: a sphere spinning about its contact normal keeps
    // its spin (the contact model has no twisting resistance), and a few such spheres kept a
    // tile at 6.4e-6 N m g r of rotational energy for seconds (measured) without any motion of
    // the bed.
    const double kinetic = d.translational_energy;
    std::fprintf(stderr,
                 "[bench] settling tile: t = %.2f s, translational energy / (N m g r) = %.2e, "
                 "rotational %.2e\n",
                 d.time, kinetic / energy_scale, d.rotational_energy / energy_scale);
    if (!std::isfinite(kinetic + d.rotational_energy))
      throw std::runtime_error("tile settling diverged");
    if (d.particles != p.tile_count)
      throw std::runtime_error("spheres escaped the tile box while settling");
    if (d.time >= 0.2 && kinetic < settled_energy)
      break;
    if (d.time > 2.0)
      throw std::runtime_error("tile did not settle within 2 s");
  }
  const kdem::ParticleSnapshot snap = engine.snapshot();
  std::vector<Sphere> spheres(snap.size());
  for (std::size_t i = 0; i < snap.size(); ++i) {
    spheres[i] = {snap.position[3 * i], snap.position[3 * i + 1], snap.position[3 * i + 2],
                  snap.radius[i]};
    for (int c = 0; c < 4; ++c)
      spheres[i].q[c] = snap.quaternion[4 * i + c];
  }
  return spheres;
}

std::vector<Sphere> load_or_settle_tile(const BenchParameters& p, const BenchShape& shape,
                                        const std::string& cache_dir) {
  const fs::path path = fs::path(cache_dir) / tile_cache_name(p, shape);
  std::vector<Sphere> spheres;
  if (std::ifstream in{path}; in) {
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#')
        continue;
      Sphere s;
      std::istringstream row(line);
      if (!(row >> s.x >> s.y >> s.z >> s.r))
        continue;
      double q[4];
      if (row >> q[0] >> q[1] >> q[2] >> q[3]) // orientation (tiles of superquadrics)
        std::copy(q, q + 4, s.q);
      spheres.push_back(s);
    }
    if (int(spheres.size()) == p.tile_count) {
      std::fprintf(stderr, "[bench] settled tile loaded from %s\n", path.string().c_str());
      return spheres;
    }
    std::fprintf(stderr, "[bench] ignoring incomplete cache %s\n", path.string().c_str());
  }
  spheres = settle_tile(p, shape);
  fs::create_directories(path.parent_path().empty() ? fs::path(".") : path.parent_path());
  const fs::path partial = path.string() + ".part";
  {
    std::ofstream out(partial);
    out << "# settled tile of " << spheres.size() << " " << shape.name << "s in a " << p.tile_size
        << " m box: x y z r (m) qw qx qy qz\n";
    out.precision(17);
    for (const Sphere& s : spheres)
      out << s.x << ' ' << s.y << ' ' << s.z << ' ' << s.r << ' ' << s.q[0] << ' ' << s.q[1] << ' '
          << s.q[2] << ' ' << s.q[3] << '\n';
  }
  fs::rename(partial, path);
  std::fprintf(stderr, "[bench] settled tile cached in %s\n", path.string().c_str());
  return spheres;
}

// kx x ky tiles, kx >= ky, as square as possible, holding at least n spheres.
void choose_layout(long long n, int tile_count, int& kx, int& ky) {
  const long long tiles = (n + tile_count - 1) / tile_count;
  ky = int(std::floor(std::sqrt(double(tiles))));
  while (ky > 1 && tiles % ky != 0)
    --ky;
  kx = int(tiles / ky);
  if (double(kx) / ky > 4) { // a poor factorisation: take a square and leave spheres out
    ky = int(std::ceil(std::sqrt(double(tiles))));
    kx = int((tiles + ky - 1) / ky);
  }
}

Bed make_bed(const BenchParameters& p, const std::vector<Sphere>& tile, long long n, bool mirror) {
  Bed bed;
  choose_layout(n, p.tile_count, bed.tiles_x, bed.tiles_y);
  const double L = p.tile_size;
  for (int ty = 0; ty < bed.tiles_y; ++ty)
    for (int tx = 0; tx < bed.tiles_x; ++tx)
      for (const Sphere& s : tile) {
        Sphere c = s;
        const bool mirror_x = mirror && tx % 2 == 1, mirror_y = mirror && ty % 2 == 1;
        c.x = tx * L + (mirror_x ? L - s.x : s.x);
        c.y = ty * L + (mirror_y ? L - s.y : s.y);
        // Mirroring x turns a body symmetric about its own axes by M R M: q -> (w, x, -y, -z).
        // A body that is not (a clump of three spheres, a pebble) is translated instead: its
        // copies meet as each met the tile's flat side walls, with small gaps the warm-up closes.
        if (mirror_x) {
          c.q[2] = -c.q[2];
          c.q[3] = -c.q[3];
        }
        if (mirror_y) {
          c.q[1] = -c.q[1];
          c.q[3] = -c.q[3];
        }
        bed.spheres.push_back(c);
      }
  if (static_cast<long long>(bed.spheres.size()) > n) {
    std::stable_sort(bed.spheres.begin(), bed.spheres.end(),
                     [](const Sphere& a, const Sphere& b) { return a.z + a.r < b.z + b.r; });
    bed.spheres.resize(std::size_t(n));
  }
  double top = 0;
  for (const Sphere& s : bed.spheres)
    top = std::max(top, s.z + s.r);
  bed.hi[0] = bed.tiles_x * L;
  bed.hi[1] = bed.tiles_y * L;
  bed.hi[2] = top + 10 * p.mean_radius;
  return bed;
}

void write_liggghts_data(const std::string& path, const Bed& bed, const BenchParameters& p) {
  const fs::path target(path);
  if (target.has_parent_path())
    fs::create_directories(target.parent_path());
  const std::string partial = path + ".part";
  {
    std::FILE* f = std::fopen(partial.c_str(), "w");
    if (!f)
      throw std::runtime_error("cannot write " + partial);
    std::fprintf(f, "LIGGGHTS data file: kdem sphere benchmark bed, %zu spheres\n\n",
                 bed.spheres.size());
    std::fprintf(f, "%zu atoms\n1 atom types\n\n", bed.spheres.size());
    const char* axes[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a)
      std::fprintf(f, "%.17g %.17g %slo %shi\n", bed.lo[a], bed.hi[a], axes[a], axes[a]);
    std::fprintf(f, "\nAtoms\n\n");
    for (std::size_t i = 0; i < bed.spheres.size(); ++i) {
      const Sphere& s = bed.spheres[i];
      std::fprintf(f, "%zu 1 %.17g %.17g %.17g %.17g %.17g\n", i + 1, 2 * s.r, p.density, s.x, s.y,
                   s.z);
    }
    if (std::fclose(f) != 0)
      throw std::runtime_error("cannot write " + partial);
  }
  fs::rename(partial, target);
}

double median(std::vector<double> v) {
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 == 1 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::string json_number(double x) {
  if (!std::isfinite(x))
    return "null";
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.10g", x);
  return buffer;
}

int run(const Options& o) {
  const BenchParameters p;
  const std::vector<Sphere> tile = load_or_settle_tile(p, o.shape, o.cache_dir);
  const Bed bed = make_bed(p, tile, o.n, o.shape.mirror_symmetric());
  if (!o.write_data.empty()) {
    write_liggghts_data(o.write_data, bed, p);
    std::fprintf(stderr, "[bench] wrote %s\n", o.write_data.c_str());
  }

  // Bytes in the engine's memory space, counted from its construction to the end of warm-up.
  auto memory = std::make_optional<kdem::KernelTimer>(false);
  kdem::SceneConfig scene = base_scene(p, o.shape, bed.lo, bed.hi);
  scene.sort_by_cell = !o.unsorted;
  if (o.ellipsoid_general_newton)
    kdem::modify_superquadric_contact(scene).ellipsoid_scalar_root = false;
  if (o.no_box_certificates)
    kdem::modify_superquadric_contact(scene).box_certificates = false;
  long long wall_triangles = 0;
  if (o.mesh_triangles > 0) {
    kdem::WallConfig& w = scene.walls[0];
    w.kind = kdem::WallConfig::Kind::Mesh;
    w.file = write_mesh_box(bed.lo, bed.hi, o.mesh_triangles, o.cache_dir, wall_triangles);
  }
  kdem::Engine engine(scene);
  const int shape_id = o.shape.is_sphere() ? 0 : engine.shape_id(o.shape.name);
  std::vector<kdem::ParticleInit> inits(bed.spheres.size());
  for (std::size_t i = 0; i < bed.spheres.size(); ++i) {
    inits[i].position = {bed.spheres[i].x, bed.spheres[i].y, bed.spheres[i].z};
    inits[i].radius = bed.spheres[i].r;
    inits[i].shape = shape_id;
    std::copy(bed.spheres[i].q, bed.spheres[i].q + 4, inits[i].orientation.begin());
  }
  if (o.unsorted) // the order of a random pour: no locality in memory
    std::shuffle(inits.begin(), inits.end(), std::mt19937_64(p.seed));
  engine.add_particles(inits);
  engine.set_rebuild_every_step(o.rebuild_every_step);

  engine.advance(o.warmup);
  Kokkos::fence();
  const double bytes = double(memory->bytes_allocated());
  const double peak_bytes = double(memory->peak_bytes());
  const std::string bytes_by_label = memory->bytes_by_label_json();
  memory.reset(); // no callbacks during the timed runs
  const kdem::Diagnostics before = engine.diagnostics();

  std::vector<double> times;
  for (int k = 0; k < o.repeat; ++k) {
    const auto start = std::chrono::steady_clock::now();
    engine.advance(o.steps);
    Kokkos::fence();
    const auto stop = std::chrono::steady_clock::now();
    times.push_back(std::chrono::duration<double>(stop - start).count());
  }
  const kdem::Diagnostics after = engine.diagnostics();
  const double median_s = median(times);
  const long long n = engine.particle_count();
  const double rate = median_s > 0 ? double(n) * double(o.steps) / median_s : 0.0;

  // One more run with every kernel fenced and timed, for the split by kernel.
  std::string kernels = "{}";
  if (o.repeat > 0) {
    kdem::KernelTimer timer(true);
    engine.advance(o.steps);
    Kokkos::fence();
    kernels = timer.kernels_json();
    std::replace(kernels.begin(), kernels.end(), '\n', ' '); // the record is one line
  }

  std::ostringstream json;
  json << "{\"code\": \"kdem\", \"shape\": \"" << o.shape.name << "\", \"backend\": \""
       << kdem::Engine::backend_name() << "\""
       << ", \"threads\": " << kdem::Engine::backend_concurrency() << ", \"n\": " << n
       << ", \"steps\": " << o.steps << ", \"repeat\": " << o.repeat << ", \"warmup\": " << o.warmup
       << ", \"rebuild_every_step\": " << (o.rebuild_every_step ? "true" : "false")
       << ", \"sorted_by_cell\": " << (o.unsorted ? "false" : "true") << ", \"walls\": \""
       << (o.mesh_triangles > 0 ? "mesh" : "planes") << "\""
       << ", \"wall_triangles\": " << wall_triangles << ", \"median_s\": " << json_number(median_s)
       << ", \"times_s\": [";
  for (std::size_t k = 0; k < times.size(); ++k)
    json << (k ? ", " : "") << json_number(times[k]);
  json << "], \"particle_steps_per_s\": " << json_number(rate)
       << ", \"pair_contacts\": " << after.pair_contacts
       << ", \"wall_contacts\": " << after.wall_contacts << ", \"contacts_per_particle\": "
       << json_number(n > 0 ? 2.0 * after.pair_contacts / double(n) : 0.0)
       << ", \"list_builds_timed\": " << (after.list_builds - before.list_builds)
       << ", \"list_builds_total\": " << after.list_builds
       << ", \"largest_overlap_ratio\": " << json_number(after.largest_overlap_ratio)
       << ", \"kinetic_energy_j\": "
       << json_number(after.translational_energy + after.rotational_energy)
       << ", \"bed\": {\"tiles\": [" << bed.tiles_x << ", " << bed.tiles_y
       << "], \"mirrored_copies\": " << (o.shape.mirror_symmetric() ? "true" : "false")
       << ", \"box_min\": [" << json_number(bed.lo[0]) << ", " << json_number(bed.lo[1]) << ", "
       << json_number(bed.lo[2]) << "], \"box_max\": [" << json_number(bed.hi[0]) << ", "
       << json_number(bed.hi[1]) << ", " << json_number(bed.hi[2]) << "]}"
       << ", \"model\": {\"density\": " << json_number(p.density)
       << ", \"youngs_modulus\": " << json_number(p.youngs)
       << ", \"poisson_ratio\": " << json_number(p.poisson)
       << ", \"restitution\": " << json_number(p.restitution)
       << ", \"friction\": " << json_number(p.friction)
       << ", \"mean_radius\": " << json_number(p.mean_radius)
       << ", \"radius_spread\": " << json_number(p.radius_spread)
       << ", \"time_step\": " << json_number(p.time_step) << ", \"skin\": " << json_number(p.skin)
       << ", \"gravity\": " << json_number(p.gravity) << "}"
       << ", \"memory\": {\"bytes_per_particle\": " << json_number(n > 0 ? bytes / n : 0.0)
       << ", \"peak_bytes_per_particle\": " << json_number(n > 0 ? peak_bytes / n : 0.0)
       << ", \"bytes_by_label\": " << bytes_by_label << "}"
       << ", \"kernels\": " << kernels << ", \"git\": \"" << kdem::git_hash() << "\"}";
  std::cout << json.str() << std::endl;
  if (!o.out.empty()) {
    const fs::path target(o.out);
    if (target.has_parent_path())
      fs::create_directories(target.parent_path());
    std::ofstream out(target);
    out << json.str() << '\n';
    if (!out)
      throw std::runtime_error("cannot write " + o.out);
  }
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  Options options;
  try {
    options = parse(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kdem_bench: %s\n%s", e.what(), usage);
    return 2;
  }
  Kokkos::ScopeGuard kokkos(argc, argv);
  kdem::install_memory_space_check<kdem::MemSpace>();
  try {
    return run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kdem_bench: %s\n", e.what());
    return 1;
  }
}
