#pragma once
// Body-frame surfaces of closed shapes for output: a latitude-longitude grid of points (poles
// included) joined by two triangles per quad.
#include <cmath>

#include "snapshot.hpp"

namespace kdem {

// Longitude steps of the surfaces that frames draw (latitude: half as many).
constexpr int output_surface_resolution = 16;

// `resolution` (even) steps of longitude omega in [0, 2 pi), resolution / 2 of latitude eta in
// [-pi / 2, pi / 2]; point(eta, omega) returns the body-frame point as std::array<double, 3>.
template <class Point> BodySurface latitude_longitude_surface(int resolution, const Point& point) {
  const double pi = 3.14159265358979323846;
  const int latitudes = resolution / 2;
  BodySurface surface;
  for (int la = 0; la <= latitudes; ++la) {
    const double eta = -0.5 * pi + pi * la / latitudes;
    for (int lo = 0; lo < resolution; ++lo) {
      const auto x = point(eta, 2 * pi * lo / resolution);
      surface.points.insert(surface.points.end(), x.begin(), x.end());
    }
  }
  auto index = [&](int la, int lo) { return la * resolution + (lo % resolution); };
  for (int la = 0; la < latitudes; ++la)
    for (int lo = 0; lo < resolution; ++lo) {
      surface.triangles.insert(surface.triangles.end(),
                               {index(la, lo), index(la, lo + 1), index(la + 1, lo + 1)});
      surface.triangles.insert(surface.triangles.end(),
                               {index(la, lo), index(la + 1, lo + 1), index(la + 1, lo)});
    }
  return surface;
}

// sgn(t) |t|^e: the signed power of the parametric surfaces of superquadrics (Barr 1981).
inline double signed_power(double t, double exponent) {
  return std::copysign(std::pow(std::abs(t), exponent), t);
}

inline BodySurface unit_sphere_surface(int resolution) {
  return latitude_longitude_surface(resolution, [](double eta, double omega) {
    return std::array<double, 3>{std::cos(eta) * std::cos(omega), std::cos(eta) * std::sin(omega),
                                 std::sin(eta)};
  });
}

} // namespace kdem
