#pragma once
// Contact-law coefficients shared by the tests that call the law directly.
#include "kernels/contact_law.hpp"

namespace kdem::testing {

// A glass-like pair: E* = 50 MPa, G* = 20 MPa, damping 0.3, friction 0.4.
inline PairCoefficients glass_pair() {
  PairCoefficients c;
  c.effective_youngs = 5e7;
  c.effective_shear = 2e7;
  c.damping = 0.3;
  c.friction = 0.4;
  return c;
}

} // namespace kdem::testing
