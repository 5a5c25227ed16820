// The dilated-polyhedron family's host setup: per scene shape the core from its mesh
// (shapes/dilated_polyhedron_build.hpp), the mass properties of core plus dilation
// (shapes/dilated_polyhedron_properties.hpp), the principal frame that becomes the body frame
// (the core moved there, centroid at the origin), the bounding radius, output fields and
// surface, and the device table with the contact settings.
#include <cmath>
#include <stdexcept>

#include "../kernels/dilated_polyhedron/family.hpp"
#include "../shapes/dilated_polyhedron_properties.hpp"
#include "dilated_polyhedron_scene.hpp"
#include "engine_state.hpp"
#include "host_copy.hpp"

namespace kdem {
namespace {

// The core in its principal frame, with the template the engine reads.
struct PrincipalCore {
  DilatedCore core;
  ShapeTemplate host;
};

PrincipalCore principal_core(const ShapeConfig& shape) {
  const DilatedPolyhedronShapeParameters& config = dilated_polyhedron_parameters(shape);
  std::vector<Vec3> points;
  for (const auto& p : config.points)
    points.push_back(Vec3{p[0], p[1], p[2]});
  PrincipalCore made;
  try {
    const DilatedCore given = build_dilated_core(points, config.triangles, config.dilation_radius);
    DilatedMassOptions options;
    options.precision = config.mass_precision;
    const BodyMassProperties mass = dilated_mass_properties(given, options);
    const Mat3 axes = principal_frame_nearest(mass.inertia_per_density, mass.principal_axes,
                                              mass.relative_precision);
    const Mat3 to_principal = transpose(axes);
    for (Vec3& p : points)
      p = to_principal * (p - mass.centroid);
    made.core = build_dilated_core(points, config.triangles, config.dilation_radius);
    const Mat3 principal = to_principal * mass.inertia_per_density * axes;
    made.host.volume = mass.volume;
    made.host.inertia_per_density = Vec3{principal.m[0][0], principal.m[1][1], principal.m[2][2]};
  } catch (const std::invalid_argument& refused) {
    throw std::runtime_error("shape '" + shape.name + "' (mesh " + config.mesh_file +
                             "): " + refused.what());
  }
  ShapeTemplate& t = made.host;
  const double r = config.dilation_radius;
  for (const CoreVertex& v : made.core.vertices)
    t.bounding_radius = std::max(t.bounding_radius, norm(v.position) + r);
  t.equivalent_radius = std::cbrt(3.0 * t.volume / (4.0 * pi));
  t.contact_features = DilatedPolyhedronFamily::contact_points;
  t.output_fields = {{"dilation_radius", 1, {r}}};
  // Output draws the core moved out by r along each vertex's angle-weighted normal: the dilated
  // surface at the vertices, a little inside it between them (docs/architecture.md).
  for (std::size_t k = 0; k < made.core.vertices.size(); ++k) {
    const Vec3 n = made.core.vertex_pseudonormals[k];
    const Vec3 x = made.core.vertices[k].position + (r / norm(n)) * n;
    t.surface.points.insert(t.surface.points.end(), {x.x, x.y, x.z});
  }
  for (const CoreFace& f : made.core.faces)
    t.surface.triangles.insert(t.surface.triangles.end(), {f.vertex[0], f.vertex[1], f.vertex[2]});
  return made;
}

DilatedContactSettings contact_settings(const FamilySettings* given) {
  DilatedPolyhedronContactConfig config;
  if (const auto* settings = dynamic_cast<const DilatedPolyhedronContactConfig*>(given))
    config = *settings;
  DilatedContactSettings settings;
  settings.slack = ConeSlack::of_angle(config.cone_slack, config.cone_fade);
  settings.averaging.weighted = config.averaging;
  settings.averaging.cos_angle = std::cos(config.averaging_angle * pi / 180.0);
  settings.merge = config.merge_distance;
  return settings;
}

} // namespace

std::vector<ShapeTemplate> DilatedPolyhedronFamily::setup_templates(const FamilyShapes& family,
                                                                    Table& table) {
  std::vector<std::vector<CoreVertex>> vertices;
  std::vector<std::vector<CoreEdge>> edges;
  std::vector<std::vector<CoreFace>> faces;
  std::vector<std::vector<Vec3>> cones;
  std::vector<std::vector<SphereNode>> nodes;
  std::vector<double> dilation, caps_reach, equivalent;
  std::vector<ShapeTemplate> templates;
  table.settings = contact_settings(family.settings);
  for (const ShapeConfig* shape : family.shapes) {
    PrincipalCore made = principal_core(*shape);
    bound_normal_cones(made.core, table.settings.slack);
    vertices.push_back(made.core.vertices);
    edges.push_back(made.core.edges);
    faces.push_back(made.core.faces);
    cones.push_back(made.core.cones);
    nodes.push_back(made.core.nodes);
    dilation.push_back(made.core.radius);
    caps_reach.push_back(made.core.caps_reach);
    equivalent.push_back(made.host.equivalent_radius);
    templates.push_back(std::move(made.host));
  }
  table.vertices = upload_ragged<CoreVertex>("dilated_vertices", vertices);
  table.edges = upload_ragged<CoreEdge>("dilated_edges", edges);
  table.faces = upload_ragged<CoreFace>("dilated_faces", faces);
  table.cones = upload_ragged<Vec3>("dilated_cones", cones);
  table.nodes = upload_ragged<SphereNode>("dilated_nodes", nodes);
  table.dilation = upload<double>("dilated_dilation", dilation);
  table.caps_reach = upload<double>("dilated_caps_reach", caps_reach);
  table.equivalent_radius = upload<double>("dilated_equivalent_radius", equivalent);
  return templates;
}

} // namespace kdem
