// Checks that an installed Kokkos + Kokkos Kernels works: a parallel_for with a
// KOKKOS_LAMBDA, a reduction, and KokkosBatched::SerialLU + SerialTrsv solving
// small dense systems inside a kernel.  Exit status 0 on success.
#include <KokkosBatched_LU_Decl.hpp>
#include <KokkosBatched_LU_Serial_Impl.hpp>
#include <KokkosBatched_Trsv_Decl.hpp>
#include <KokkosBatched_Trsv_Serial_Impl.hpp>
#include <Kokkos_Core.hpp>

#include <cmath>
#include <cstdio>

int main(int argc, char* argv[]) {
  int failures = 0;
  Kokkos::initialize(argc, argv);
  {
    using exec = Kokkos::DefaultExecutionSpace;
    constexpr int n = 1000, m = 4;
    std::printf("execution space: %s\n", exec::name());

    Kokkos::View<double*> x("x", n);
    Kokkos::parallel_for(
        "fill", Kokkos::RangePolicy<exec>(0, n), KOKKOS_LAMBDA(const int i) { x(i) = 2.0 * i; });
    double sum = 0.0;
    Kokkos::parallel_reduce(
        "sum", Kokkos::RangePolicy<exec>(0, n),
        KOKKOS_LAMBDA(const int i, double& s) { s += x(i); }, sum);
    if (std::abs(sum - double(n) * (n - 1)) > 1e-9) {
      std::printf("reduction: got %g\n", sum);
      ++failures;
    }

    // Batched LU: A = I*(m+1) + 1 (diagonally dominant, no pivoting needed),
    // b = A * [1..m]; solve in place and compare with [1..m].
    Kokkos::View<double***> A("A", n, m, m);
    Kokkos::View<double**> b("b", n, m);
    Kokkos::parallel_for(
        "lu", Kokkos::RangePolicy<exec>(0, n), KOKKOS_LAMBDA(const int k) {
          auto a = Kokkos::subview(A, k, Kokkos::ALL(), Kokkos::ALL());
          auto r = Kokkos::subview(b, k, Kokkos::ALL());
          for (int i = 0; i < m; ++i) {
            double s = 0.0;
            for (int j = 0; j < m; ++j) {
              a(i, j) = (i == j ? m + 1.0 + k % 7 : 1.0);
              s += a(i, j) * (j + 1);
            }
            r(i) = s;
          }
          KokkosBatched::SerialLU<KokkosBatched::Algo::LU::Unblocked>::invoke(a);
          KokkosBatched::SerialTrsv<KokkosBatched::Uplo::Lower, KokkosBatched::Trans::NoTranspose,
                                    KokkosBatched::Diag::Unit,
                                    KokkosBatched::Algo::Trsv::Unblocked>::invoke(1.0, a, r);
          KokkosBatched::SerialTrsv<KokkosBatched::Uplo::Upper, KokkosBatched::Trans::NoTranspose,
                                    KokkosBatched::Diag::NonUnit,
                                    KokkosBatched::Algo::Trsv::Unblocked>::invoke(1.0, a, r);
        });
    double err = 0.0;
    Kokkos::parallel_reduce(
        "err", Kokkos::RangePolicy<exec>(0, n),
        KOKKOS_LAMBDA(const int k, double& e) {
          for (int i = 0; i < m; ++i)
            e = Kokkos::Experimental::fmax(e, Kokkos::Experimental::fabs(b(k, i) - (i + 1)));
        },
        Kokkos::Max<double>(err));
    if (!(err < 1e-12)) {
      std::printf("batched LU: max error %g\n", err);
      ++failures;
    }
    std::printf("reduction %g, batched LU max error %g\n", sum, err);
  }
  Kokkos::finalize();
  std::printf(failures ? "FAILED\n" : "OK\n");
  return failures ? 1 : 0;
}
