// The ragged template table: rows of different lengths (none, one, several) uploaded from the
// host and read back inside a kernel, element for element and in order.
#include <gtest/gtest.h>

#include <vector>

#include "kernels/ragged_table.hpp"
#include "src/host_copy.hpp"

namespace kdem {
namespace {

// Writes row t's size and the sum of its values times their position, per row (a functor: nvcc
// takes no device lambda in a test body).
struct SummariseRows {
  RaggedTable<double> table;
  IndexView sizes;
  ScalarView weighted;
  KOKKOS_INLINE_FUNCTION void operator()(int t) const {
    sizes(t) = table.size(t);
    double sum = 0;
    for (int m = 0; m < table.size(t); ++m)
      sum += (m + 1) * table(t, m);
    weighted(t) = sum;
  }
};

TEST(RaggedTable, RowsOfAnyLengthReadBackInOrder) {
  const std::vector<std::vector<double>> rows{{1.5}, {}, {2, 3, 5, 7}, {11, 13}};
  const RaggedTable<double> table = upload_ragged<double>("test_rows", rows);
  ASSERT_EQ(table.rows(), 4);
  SummariseRows summary{table, IndexView("sizes", 4), ScalarView("weighted", 4)};
  Kokkos::parallel_for("kdem::test_ragged_rows", RangePolicy(0, 4), summary);
  const std::vector<int> sizes = flatten_to_host(summary.sizes, 4);
  const std::vector<double> weighted = flatten_to_host(summary.weighted, 4);
  for (int t = 0; t < 4; ++t) {
    double expected = 0;
    for (std::size_t m = 0; m < rows[t].size(); ++m)
      expected += double(m + 1) * rows[t][m];
    EXPECT_EQ(sizes[t], int(rows[t].size())) << "row " << t;
    EXPECT_EQ(weighted[t], expected) << "row " << t; // small integers: exact
  }
}

TEST(RaggedTable, AnEmptyTableHasNoRows) {
  EXPECT_EQ(RaggedTable<double>{}.rows(), 0);
  EXPECT_EQ(upload_ragged<double>("no_rows", std::vector<std::vector<double>>{}).rows(), 0);
}

} // namespace
} // namespace kdem
