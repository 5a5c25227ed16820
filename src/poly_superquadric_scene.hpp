#pragma once
// The poly-superquadric family's scene keys (poly_superquadric_scene.cpp): a shape entry
// `poly_superquadric: {half_axes_plus, half_axes_minus, blockiness}` (book Eqs. 3.17 to 3.25) and
// the `poly_superquadric_contact` settings.
#include "family_scene.hpp"
#include "snapshot.hpp"

namespace kdem {

// Extents from the origin O0 along +x, +y, +z (r_x+, r_y+, r_z+) and along -x, -y, -z of the
// octant frame, and the blockiness n1 (profile along z), n2 (xy cross-section) shared by the
// eight octants.
struct PolySuperquadricShapeParameters : FamilyShapeParameters {
  Vec3d half_axes_plus{0, 0, 0};  // m
  Vec3d half_axes_minus{0, 0, 0}; // m
  double n1 = 2, n2 = 2;
  // The smallest half-width (r+ + r-) / 2 over the axes: a thin half's own extent would make the
  // default skin, and so the list builds, follow a cap that is not a size of the body.
  double smallest_size() const override;
};

// Its entry in the registry of scene readers.
FamilyScene poly_superquadric_scene();

// The parameters of a poly-superquadric shape entry; throws std::logic_error for another
// family's.
const PolySuperquadricShapeParameters& poly_superquadric_parameters(const ShapeConfig& shape);
// The surface in the octant frame about O0 on the latitude-longitude grid of body_surface.hpp
// (Barr's parametric surface with each octant's semi-axes), for output.
BodySurface poly_superquadric_surface(const PolySuperquadricShapeParameters& shape, int resolution);
// A poly-superquadric shape entry made in code.
ShapeConfig poly_superquadric_shape_config(const std::string& name, Vec3d half_axes_plus,
                                           Vec3d half_axes_minus, double n1, double n2);

} // namespace kdem
