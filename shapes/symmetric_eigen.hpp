#pragma once
// Eigen-decomposition of a symmetric 3 x 3 matrix by cyclic Jacobi rotations (Golub & Van Loan,
// "Matrix Computations", 4th ed., Sect. 8.5; the update formulas of Press et al., "Numerical
// Recipes", 3rd ed., Sect. 11.1). Jacobi rather than the closed-form cubic: it is accurate to
// rounding also for close and repeated eigenvalues (the principal moments of near-symmetric
// particles), and every eigenvector comes out orthonormal. Host code (plain inline C++), used once
// per particle template; no branch depends on anything but the input, so the same matrix gives the
// same bits.
#include <algorithm>
#include <cmath>

#include "mat3.hpp"

namespace kdem {

struct SymmetricEigen {
  Vec3 values;  // ascending
  Mat3 vectors; // columns: unit eigenvectors in the order of `values`, det = +1
};

namespace symmetric_eigen_detail {

// One Jacobi rotation in the (p, q) plane, A <- J^T A J and V <- V J with J = [[c, s], [-s, c]] in
// rows and columns p, q, chosen so that the new a_pq is zero. t, the tangent of the rotation
// angle, is the smaller root of t^2 + 2 tau t - 1 = 0, tau = (a_qq - a_pp) / (2 a_pq) (angle
// <= pi / 4: the stable choice, Golub & Van Loan Alg. 8.5.1), written so that it neither
// overflows nor cancels.
inline void rotate(double (&a)[3][3], double (&v)[3][3], int p, int q) {
  const double apq = a[p][q];
  if (apq == 0.0)
    return;
  const double tau = (a[q][q] - a[p][p]) / (2.0 * apq);
  const double t = std::fabs(tau) > 1e150
                       ? 0.5 / tau
                       : (tau >= 0 ? 1.0 : -1.0) / (std::fabs(tau) + std::sqrt(1.0 + tau * tau));
  const double c = 1.0 / std::sqrt(1.0 + t * t), s = t * c;
  const int r = 3 - p - q; // the third index
  const double arp = a[r][p], arq = a[r][q];
  a[r][p] = a[p][r] = c * arp - s * arq;
  a[r][q] = a[q][r] = s * arp + c * arq;
  a[p][p] -= t * apq;
  a[q][q] += t * apq;
  a[p][q] = a[q][p] = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double vkp = v[k][p], vkq = v[k][q];
    v[k][p] = c * vkp - s * vkq;
    v[k][q] = s * vkp + c * vkq;
  }
}

} // namespace symmetric_eigen_detail

// The eigenvalues (ascending) and eigenvectors of the symmetric part of `m` (only the upper
// triangle is read). Sweeps the three off-diagonal entries until their norm is below 1e-15 of the
// Frobenius norm (Jacobi converges quadratically: a handful of sweeps; 64 is a cap that is never
// reached in practice). Each eigenvector's largest component is made positive, then the last
// column's sign is chosen for det = +1, so that the axes form a rotation matrix.
inline SymmetricEigen symmetric_eigen(const Mat3& m) {
  double a[3][3], v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int r = 0; r < 3; ++r)
    for (int k = r; k < 3; ++k)
      a[r][k] = a[k][r] = m.m[r][k];
  double frobenius2 = 0;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      frobenius2 += a[r][k] * a[r][k];
  const double tolerance2 = 1e-30 * frobenius2; // (1e-15 |A|_F)^2
  for (int sweep = 0; sweep < 64; ++sweep) {
    const double off2 = 2.0 * (a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2]);
    if (off2 <= tolerance2)
      break;
    symmetric_eigen_detail::rotate(a, v, 0, 1);
    symmetric_eigen_detail::rotate(a, v, 0, 2);
    symmetric_eigen_detail::rotate(a, v, 1, 2);
  }

  // Ascending order; ties keep the index order (a fixed sorting network of three compares).
  int order[3] = {0, 1, 2};
  const auto swap_if_greater = [&](int i, int j) {
    if (a[order[i]][order[i]] > a[order[j]][order[j]]) {
      const int keep = order[i];
      order[i] = order[j];
      order[j] = keep;
    }
  };
  swap_if_greater(0, 1);
  swap_if_greater(1, 2);
  swap_if_greater(0, 1);

  SymmetricEigen result;
  result.values = {a[order[0]][order[0]], a[order[1]][order[1]], a[order[2]][order[2]]};
  for (int k = 0; k < 3; ++k) {
    Vec3 e{v[0][order[k]], v[1][order[k]], v[2][order[k]]};
    e = (1.0 / norm(e)) * e; // orthonormal to rounding already; this only trims the last bits
    int largest = 0;
    for (int i = 1; i < 3; ++i)
      if (std::fabs(e[i]) > std::fabs(e[largest]))
        largest = i;
    if (e[largest] < 0)
      e = -e;
    result.vectors.m[0][k] = e.x, result.vectors.m[1][k] = e.y, result.vectors.m[2][k] = e.z;
  }
  const Vec3 c0 = column(result.vectors, 0), c1 = column(result.vectors, 1),
             c2 = column(result.vectors, 2);
  if (dot(cross(c0, c1), c2) < 0)
    for (int r = 0; r < 3; ++r)
      result.vectors.m[r][2] = -result.vectors.m[r][2];
  return result;
}

// Products of inertia below this fraction of the trace count as zero: the body's own frame is
// then principal (rounding of closed forms is ~1e-16 of it).
constexpr double diagonal_tolerance = 1e-12;

inline bool is_diagonal(const Mat3& tensor, double tolerance = diagonal_tolerance) {
  const double scale = tolerance * trace(tensor);
  return std::fabs(tensor.m[0][1]) <= scale && std::fabs(tensor.m[0][2]) <= scale &&
         std::fabs(tensor.m[1][2]) <= scale;
}

// The principal frame of `tensor` (its eigenvectors as columns) whose axes are ordered and
// signed to lie closest to the frame it is written in, so that a body's principal frame is its own
// frame (a poly-superquadric's octant frame, a clump's scene frame) wherever that is principal,
// and turns away from it only as far as the products of inertia make it. Right-handed.
// `precision`: the relative error of a numerically integrated tensor (in units of its trace);
// products of inertia within it are noise, and the body's own frame is kept (an axisymmetric
// body's two equal moments would otherwise let the noise turn its frame about the axis by any
// angle).
inline Mat3 principal_frame_nearest(const Mat3& tensor, const Mat3& eigenvectors,
                                    double precision = 0) {
  if (is_diagonal(tensor, std::max(diagonal_tolerance, precision)))
    return identity3();
  Mat3 axes;
  bool taken[3] = {false, false, false};
  for (int axis = 0; axis < 3; ++axis) {
    int best = -1;
    for (int k = 0; k < 3; ++k)
      if (!taken[k] &&
          (best < 0 || std::fabs(eigenvectors.m[axis][k]) > std::fabs(eigenvectors.m[axis][best])))
        best = k;
    taken[best] = true;
    const double sign = eigenvectors.m[axis][best] < 0 ? -1.0 : 1.0;
    for (int r = 0; r < 3; ++r)
      axes.m[r][axis] = sign * eigenvectors.m[r][best];
  }
  const Vec3 z = cross(column(axes, 0), column(axes, 1));
  for (int r = 0; r < 3; ++r)
    axes.m[r][2] = z[r];
  return axes;
}

} // namespace kdem
