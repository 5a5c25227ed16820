// GoogleTest main for suites that need Kokkos.
#include <Kokkos_Core.hpp>
#include <gtest/gtest.h>

#include <cstdlib>

#include "kernels/types.hpp"

namespace kdem::testing {
extern const char* const source_dir;
const char* const source_dir = KDEM_SOURCE_DIR;
} // namespace kdem::testing

int main(int argc, char** argv) {
  setenv("OMP_PROC_BIND", "false", 0); // test runs share cores with other tests
  Kokkos::ScopeGuard kokkos(argc, argv);
  kdem::install_memory_space_check<kdem::MemSpace>();
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
