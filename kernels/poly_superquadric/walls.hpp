#pragma once
// Poly-superquadric particles against walls: the superquadrics' wall contact over the piecewise
// surface (the deepest point is the support point of the octant the wall's inward direction points
// into; triangle features and cylinders by the convex wall numerics of kernels/surface_walls.hpp).
#include "../superquadric/walls.hpp"
#include "family.hpp"

namespace kdem {

inline PolySuperquadricWallContact
PolySuperquadricFamily::wall_contact(const Table& t, const ShapeFamilies& s,
                                     const WallElements& elements, const ParticleViews& p) {
  return PolySuperquadricWallContact{elements, t, s, p, t.settings.curvature_limit};
}

} // namespace kdem
