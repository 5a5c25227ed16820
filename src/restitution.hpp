#pragma once
// Damping coefficient of the Hertz-Mindlin law for a given coefficient of restitution.
//
// With F_n = k d^1.5 + gamma sqrt(1.5 k m*) d^0.25 d', k = 4/3 E* sqrt(R*), the scaled overlap
// X = d / L and time T = t / tau, tau^2 = m* / (k sqrt(L)), obey
//   X'' = -X^1.5 - gamma sqrt(1.5) X^0.25 X',
// for every impact velocity, radius, mass and modulus: the restitution depends on gamma alone
// (Tsuji et al., Powder Technol. 71 (1992) 239). The closed form
//   gamma = -2 sqrt(5/6) ln e / sqrt(ln^2 e + pi^2)
// (the one of LIGGGHTS and EDEM) reproduces e to about 1e-6; restitution_for_damping integrates
// the scaled equation so that tests can check it.
namespace kdem {

double damping_for_restitution(double e);

// Restitution of the scaled Hertz impact with damping coefficient gamma (>= 0), by RK4.
double restitution_for_damping(double gamma);

} // namespace kdem
