#pragma once
// Builders of dilated-polyhedron cores (book chapter 4; digest ch4_5 A1.2-A1.6), host only: the
// offset Fibonacci lattice of unit directions, its triangulation by convex hull, the radial maps
// of a superquadric and of a spherical-harmonic surface onto it, the convex hull of any points
// (qhull) and mesh simplification (VTK's quadric decimation). Every builder returns a closed,
// outward-wound triangle mesh or throws std::invalid_argument saying what is wrong.
#include <array>
#include <complex>
#include <vector>

#include "mesh.hpp"

namespace kdem {

using Point3 = std::array<double, 3>;

// Book Eq. 4.3, the offset Fibonacci lattice: direction i of `count` has azimuth 2 pi i / lambda
// (lambda the golden ratio) and polar angle arccos(1 - 2 (i + eps) / (count - 1 + 2 eps)), eps =
// 0.36. Needs count >= 4.
std::vector<Point3> fibonacci_directions(int count);

// The convex hull of `points`, outward wound, holding only the points that are its vertices
// (renumbered in their input order). Refuses fewer than 4 points and points that span no volume
// (all coincident, collinear or coplanar).
TriangleMesh convex_hull_core(const std::vector<Point3>& points);

// The hull of `count` Fibonacci directions: every direction a vertex (all lie on the unit sphere),
// 2 count - 4 triangles (a closed triangulated sphere: V - E + F = 2 with 3F = 2E).
TriangleMesh fibonacci_sphere(int count);

// The superquadric F = (|x/a|^n2 + |y/b|^n2)^(n1/n2) + |z/c|^n1 - 1 (shapes/superquadric.hpp),
// sampled at `nodes` Fibonacci directions u as r(u) u, r(u) = G(u)^(-1/n1) with G(u) = F(u) + 1
// (F + 1 is homogeneous of degree n1). Needs a, b, c > 0 and n1, n2 > 0.
TriangleMesh superquadric_core(double a, double b, double c, double n1, double n2, int nodes);

// A_nm = real + i imag of the surface r(theta, phi) = Re sum_{n, m} A_nm Y_n^m(theta, phi).
struct HarmonicCoefficient {
  int n = 0, m = 0; // degree n >= 0 and order 0 <= m <= n; A_{n,-m} = (-1)^m conj(A_nm)
  double real = 0, imag = 0;
};

// Y_n^m(theta, phi) for m >= 0: orthonormal on the unit sphere, with the Condon-Shortley phase
// (digest A1.3); theta the polar angle from +z, phi the azimuth from +x.
std::complex<double> spherical_harmonic(int n, int m, double theta, double phi);

// r(theta, phi) of the coefficients; each (n, m) at most once, m >= 0 (negative m implied).
double harmonic_radius(const std::vector<HarmonicCoefficient>& coefficients, double theta,
                       double phi);

// The surface sampled at `nodes` Fibonacci directions; refuses coefficients that give a radius
// that is not positive at one of them, or a coefficient with m < 0, m > n or repeated.
TriangleMesh harmonic_core(const std::vector<HarmonicCoefficient>& coefficients, int nodes);

// The mesh reduced to about `target_faces` triangles by quadric-error edge collapse with volume
// preservation (VTK's vtkQuadricDecimation): flat regions go first, sharp edges and corners stay.
// Refuses a target below 4 or not below the mesh's count, and a result that is not closed and
// consistently wound.
TriangleMesh simplify_core(const TriangleMesh& mesh, int target_faces);

// The zero level set of a grid of values (node (i, j, k) at origin + spacing (i, j, k), its
// value at i + nx (j + ny k)) as a triangle mesh, by VTK's flying edges (marching cubes):
// how a level-set body is drawn. Refuses a grid without a sign change.
TriangleMesh zero_level_surface(const Point3& origin, double spacing,
                                const std::array<int, 3>& nodes, const std::vector<double>& values);

// The volume the mesh encloses (positive for an outward-wound closed mesh).
double enclosed_volume(const TriangleMesh& mesh);

} // namespace kdem
