#include "restitution.hpp"

#include <cmath>
#include <stdexcept>

namespace kdem {
namespace {

struct ScaledState {
  double overlap, rate;
};

ScaledState derivative(const ScaledState& s, double damping) {
  const double x = s.overlap > 0 ? s.overlap : 0.0;
  return {s.rate, -std::pow(x, 1.5) - damping * std::sqrt(1.5) * std::pow(x, 0.25) * s.rate};
}

ScaledState rk4_step(const ScaledState& s, double damping, double h) {
  auto add = [](const ScaledState& a, const ScaledState& b, double f) {
    return ScaledState{a.overlap + f * b.overlap, a.rate + f * b.rate};
  };
  const ScaledState k1 = derivative(s, damping);
  const ScaledState k2 = derivative(add(s, k1, 0.5 * h), damping);
  const ScaledState k3 = derivative(add(s, k2, 0.5 * h), damping);
  const ScaledState k4 = derivative(add(s, k3, h), damping);
  return {s.overlap + h / 6 * (k1.overlap + 2 * k2.overlap + 2 * k3.overlap + k4.overlap),
          s.rate + h / 6 * (k1.rate + 2 * k2.rate + 2 * k3.rate + k4.rate)};
}

} // namespace

double restitution_for_damping(double gamma) {
  const double h = 2e-4; // elastic contact lasts about 3.2 scaled time units
  ScaledState s{0.0, 1.0};
  for (long step = 0; step < 50'000'000; ++step) {
    const ScaledState next = rk4_step(s, gamma, h);
    if (next.overlap <= 0 && next.rate < 0) {
      const double fraction = s.overlap / (s.overlap - next.overlap);
      return -(s.rate + fraction * (next.rate - s.rate));
    }
    if (next.rate >= 0 && next.overlap <= 0)
      return 0.0;
    s = next;
  }
  return 0.0;
}

double damping_for_restitution(double e) {
  if (!(e > 0 && e <= 1))
    throw std::invalid_argument("restitution must lie in (0, 1]");
  const double log_e = std::log(e);
  return -2.0 * std::sqrt(5.0 / 6.0) * log_e / std::sqrt(log_e * log_e + M_PI * M_PI);
}

} // namespace kdem
