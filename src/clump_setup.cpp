// The clump family's host setup: per scene shape, its elements (checked to form one connected
// body), scaled to the volume-equivalent diameter where the scene asks, the union's mass
// properties (shapes/clump_properties.hpp), the principal frame that becomes the particle's body
// frame, the elements placed in it with their bounding and equivalent radii, the output fields
// and surface, the device table and the contact settings.
#include <cmath>
#include <stdexcept>
#include <string>

#include "../shapes/clump_properties.hpp"
#include "body_surface.hpp"
#include "clump_scene.hpp"
#include "engine_state.hpp"
#include "host_copy.hpp"
#include "superquadric_settings.hpp"

namespace kdem {
namespace {

// The equal-volume scaling is repeated until the factor is this close to 1 (digest ch3
// Sect. 1.3, the book's tolerance); the union grid scales with the clump, so one step suffices
// up to rounding.
constexpr double scale_tolerance = 1e-8;
constexpr int most_scaling_steps = 4;

std::vector<ClumpElement> elements_of(const ClumpShapeParameters& config) {
  std::vector<ClumpElement> elements;
  for (const ClumpElementParameters& e : config.elements) {
    const auto& q = e.orientation;
    elements.push_back(ClumpElement{
        make_superquadric(e.half_axes[0], e.half_axes[1], e.half_axes[2], e.n1, e.n2),
        Vec3{e.position[0], e.position[1], e.position[2]}, Quat{q[0], q[1], q[2], q[3]}});
  }
  return elements;
}

[[noreturn]] void refuse(const std::string& shape, const std::string& why) {
  throw std::runtime_error("shape '" + shape + "' (clump): " + why);
}

// The elements scaled together so that the union has the volume of a sphere of `diameter`.
std::vector<ClumpElement> equal_volume(std::vector<ClumpElement> elements, double diameter,
                                       double precision, ClumpMassProperties& mass) {
  const double target = pi * diameter * diameter * diameter / 6.0;
  for (int step = 0; step < most_scaling_steps; ++step) {
    const double sigma = equal_volume_scale(target, mass.volume);
    if (std::fabs(sigma - 1.0) <= scale_tolerance)
      break;
    elements = scaled_clump(elements, sigma);
    mass = clump_mass_properties(elements, precision);
  }
  return elements;
}

// Element surfaces joined into one mesh (each drawn whole: the parts inside other elements are
// hidden by them), in the principal frame.
BodySurface union_surface(const ClumpShapeParameters& config,
                          const std::vector<ClumpElementTemplate>& placed) {
  BodySurface surface;
  for (std::size_t m = 0; m < placed.size(); ++m) {
    const ClumpElementTemplate& e = placed[m];
    const Vec3d axes{e.shape.a, e.shape.b, e.shape.c};
    const BodySurface own = superquadric_surface(axes, config.elements[m].n1, config.elements[m].n2,
                                                 output_surface_resolution);
    const int offset = int(surface.points.size() / 3);
    for (std::size_t p = 0; p + 2 < own.points.size(); p += 3) {
      const Vec3 x = e.centre + e.axes * Vec3{own.points[p], own.points[p + 1], own.points[p + 2]};
      surface.points.insert(surface.points.end(), {x.x, x.y, x.z});
    }
    for (int t : own.triangles)
      surface.triangles.push_back(t + offset);
  }
  return surface;
}

struct PrincipalForm {
  std::vector<ClumpElementTemplate> elements;
  ShapeTemplate host;
};

PrincipalForm principal_form(const ShapeConfig& shape) {
  const ClumpShapeParameters& config = clump_parameters(shape);
  std::vector<ClumpElement> elements = elements_of(config);
  if (!clump_is_connected(elements))
    refuse(shape.name, "its elements do not form one connected body (elements that only touch, "
                       "or lie apart, are not joined); expected every element to overlap the rest");
  ClumpMassProperties mass = clump_mass_properties(elements, config.union_precision);
  if (config.equivalent_diameter > 0)
    elements = equal_volume(elements, config.equivalent_diameter, config.union_precision, mass);
  if (!(mass.volume > 0))
    refuse(shape.name, "its union has no volume");
  const Mat3 axes = principal_frame_nearest(mass.inertia_per_density, mass.principal_axes);
  const Mat3 to_principal = transpose(axes);
  PrincipalForm form;
  const std::vector<double> reach = clump_element_bounding_radii(elements);
  for (std::size_t m = 0; m < elements.size(); ++m) {
    const ClumpElement& e = elements[m];
    ClumpElementTemplate t;
    t.shape = e.shape;
    t.centre = to_principal * (e.centre - mass.centroid);
    t.axes = to_principal * rotation_matrix(e.orientation);
    t.bounding_radius = config.elements[m].sphere ? e.shape.a : reach[m];
    t.equivalent_radius = std::cbrt(3.0 * superquadric_volume(e.shape) / (4.0 * pi));
    t.is_sphere = config.elements[m].sphere ? 1 : 0;
    form.elements.push_back(t);
  }
  const Mat3 principal = to_principal * mass.inertia_per_density * axes;
  ShapeTemplate& t = form.host;
  t.volume = mass.volume;
  t.inertia_per_density = Vec3{principal.m[0][0], principal.m[1][1], principal.m[2][2]};
  t.bounding_radius = clump_bounding_radius(elements, mass.centroid);
  t.equivalent_radius = std::cbrt(3.0 * t.volume / (4.0 * pi));
  t.contact_features = int(elements.size());
  t.output_fields = {{"clump_elements", 1, {double(elements.size())}}};
  t.surface = union_surface(config, form.elements);
  return form;
}

ClumpContactSettings device_settings(const FamilySettings* scene_settings) {
  ClumpContactSettings settings;
  settings.newton = superquadric_device_settings(scene_settings);
  if (scene_settings != nullptr) {
    const auto& config = dynamic_cast<const ClumpContactConfig&>(*scene_settings);
    settings.seam.weighted = config.seam_weighted;
    settings.seam.distance = config.seam_distance;
    settings.seam.cos_angle = std::cos(config.seam_angle * pi / 180.0);
  }
  return settings;
}

} // namespace

std::vector<ShapeTemplate> ClumpFamily::setup_templates(const FamilyShapes& family, Table& table) {
  std::vector<ShapeTemplate> templates;
  std::vector<std::vector<ClumpElementTemplate>> elements;
  std::vector<double> equivalent_radius;
  for (const ShapeConfig* shape : family.shapes) {
    PrincipalForm form = principal_form(*shape);
    elements.push_back(std::move(form.elements));
    equivalent_radius.push_back(form.host.equivalent_radius);
    templates.push_back(std::move(form.host));
  }
  table.elements = upload_ragged<ClumpElementTemplate>("clump_elements", elements);
  table.equivalent_radius = upload<double>("clump_equivalent_radius", equivalent_radius);
  table.settings = device_settings(family.settings);
  return templates;
}

} // namespace kdem
