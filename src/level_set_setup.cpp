// The level-set family's host setup: per scene shape the mesh's exact mass properties and
// principal frame (the body frame: centroid at the origin), the signed-distance grid and surface
// points there (shapes/level_set_build.hpp), the bounding radius, output fields, the surface drawn
// (the grid's zero level set), and the device table with the contact settings. Templates hold
// the grids; particles hold only a template index.
#include <cmath>
#include <stdexcept>

#include "../kernels/level_set/family.hpp"
#include "../shapes/level_set_build.hpp"
#include "core_builders.hpp"
#include "engine_state.hpp"
#include "host_copy.hpp"
#include "level_set_scene.hpp"

namespace kdem {
namespace {

struct PrincipalLevelSet {
  LevelSetBody body;
  ShapeTemplate host;
};

// The mesh moved to its principal frame (centroid at the origin, axes along the principal axes).
std::vector<Vec3> principal_points(const LevelSetShapeParameters& config, ShapeTemplate& host) {
  std::vector<Vec3> points;
  for (const auto& p : config.points)
    points.push_back(Vec3{p[0], p[1], p[2]});
  const BodyMassProperties mass = mesh_mass_properties(points, config.triangles);
  const Mat3 axes = principal_frame_nearest(mass.inertia_per_density, mass.principal_axes, 0.0);
  const Mat3 to_principal = transpose(axes);
  for (Vec3& p : points)
    p = to_principal * (p - mass.centroid);
  const Mat3 principal = to_principal * mass.inertia_per_density * axes;
  host.volume = mass.volume;
  host.inertia_per_density = Vec3{principal.m[0][0], principal.m[1][1], principal.m[2][2]};
  return points;
}

// Frames draw the grid's zero level set (the surface the contacts see), reduced to at most this
// many triangles by quadric-error edge collapse: a grid of 40 cells across gives 8,000 to 40,000
// triangles per body, and a frame repeats them for every particle. Where the reduction refuses
// (a surface it cannot keep closed), the whole surface is drawn.
constexpr int drawn_faces = 2000;

BodySurface drawn_surface(const LevelSetBody& body) {
  const LevelSetGrid& g = body.grid;
  TriangleMesh surface = zero_level_surface({g.origin.x, g.origin.y, g.origin.z}, g.spacing,
                                            {g.nx, g.ny, g.nz}, body.values);
  if (surface.triangles.size() > std::size_t(drawn_faces)) {
    try {
      surface = simplify_core(surface, drawn_faces);
    } catch (const std::invalid_argument&) {
    }
  }
  const bool inward = enclosed_volume(surface) < 0; // flying edges winds its triangles inward
  BodySurface drawn;
  for (const auto& p : surface.points)
    drawn.points.insert(drawn.points.end(), {p[0], p[1], p[2]});
  for (const auto& t : surface.triangles)
    drawn.triangles.insert(drawn.triangles.end(),
                           {t[0], inward ? t[2] : t[1], inward ? t[1] : t[2]});
  return drawn;
}

PrincipalLevelSet principal_level_set(const ShapeConfig& shape) {
  const LevelSetShapeParameters& config = level_set_parameters(shape);
  PrincipalLevelSet made;
  try {
    const std::vector<Vec3> points = principal_points(config, made.host);
    LevelSetOptions options;
    options.spacing = config.grid_spacing;
    options.padding = config.padding;
    options.point_spacing = config.point_spacing;
    options.point_count = config.point_count;
    made.body = build_level_set(points, config.triangles, options);
    made.host.surface = drawn_surface(made.body);
  } catch (const std::invalid_argument& refused) {
    throw std::runtime_error("shape '" + shape.name + "' (mesh " + config.mesh_file +
                             "): " + refused.what());
  }
  ShapeTemplate& t = made.host;
  t.bounding_radius = made.body.bounding_radius;
  t.equivalent_radius = std::cbrt(3.0 * t.volume / (4.0 * pi));
  t.contact_features = LevelSetFamily::contact_points;
  t.output_fields = {{"grid_spacing", 1, {config.grid_spacing}},
                     {"surface_points", 1, {double(made.body.surface_points.size())}}};
  return made;
}

LevelSetContactSettings contact_settings(const FamilySettings* given) {
  LevelSetContactConfig config;
  if (const auto* settings = dynamic_cast<const LevelSetContactConfig*>(given))
    config = *settings;
  LevelSetContactSettings settings;
  settings.averaging.weighted = config.averaging;
  settings.averaging.cos_angle = std::cos(config.averaging_angle * pi / 180.0);
  settings.merge = config.merge_distance;
  settings.both_ways = config.both_ways;
  return settings;
}

} // namespace

std::vector<ShapeTemplate> LevelSetFamily::setup_templates(const FamilyShapes& family,
                                                           Table& table) {
  std::vector<std::vector<double>> values;
  std::vector<std::vector<Vec3>> points;
  std::vector<std::vector<int>> cell_first;
  std::vector<LevelSetGrid> grids;
  std::vector<LevelSetPointCells> cells;
  std::vector<double> reach, equivalent;
  std::vector<ShapeTemplate> templates;
  table.settings = contact_settings(family.settings);
  for (const ShapeConfig* shape : family.shapes) {
    PrincipalLevelSet made = principal_level_set(*shape);
    values.push_back(std::move(made.body.values));
    points.push_back(std::move(made.body.surface_points));
    cell_first.push_back(std::move(made.body.cell_first));
    grids.push_back(made.body.grid);
    cells.push_back(made.body.cells);
    reach.push_back(made.host.bounding_radius);
    equivalent.push_back(made.host.equivalent_radius);
    templates.push_back(std::move(made.host));
  }
  table.values = upload_ragged<double>("level_set_values", values);
  table.points = upload_ragged<Vec3>("level_set_points", points);
  table.cell_first = upload_ragged<int>("level_set_cell_first", cell_first);
  table.grids = upload<LevelSetGrid>("level_set_grids", grids);
  table.cells = upload<LevelSetPointCells>("level_set_cells", cells);
  table.reach = upload<double>("level_set_reach", reach);
  table.equivalent_radius = upload<double>("level_set_equivalent_radius", equivalent);
  return templates;
}

} // namespace kdem
