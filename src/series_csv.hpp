#pragma once
// Time series as CSV: one header line of column names, then one line per row. Rows are kept in
// memory (already formatted) and the whole file is rewritten atomically on flush(), so the file
// on disk is always complete.
//
// Number format: each value is written in the shortest decimal form that reads back as exactly
// the same double (std::to_chars), e.g. "0.1", "1e-07", "12345" (integers such as a step count
// print without a decimal point, exactly up to 2^53). Non-finite values are written as "nan",
// "inf" and "-inf", which numpy and pandas read. The format does not depend on the C locale.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace kdem {

class SeriesCsv {
public:
  // Throws std::invalid_argument for no columns.
  SeriesCsv(std::filesystem::path path, std::vector<std::string> columns);
  // Writes pending rows (best effort: a failure is reported on stderr, never thrown).
  ~SeriesCsv();
  SeriesCsv(const SeriesCsv&) = delete;
  SeriesCsv& operator=(const SeriesCsv&) = delete;

  // Throws std::invalid_argument unless values has one entry per column.
  void add_row(const std::vector<double>& values);
  // Rewrites the file with every row so far; does nothing when no row was added since the last
  // flush (except the first time: an empty series still gets its header line).
  void flush();

  const std::filesystem::path& path() const { return path_; }
  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t row_count() const { return row_count_; }
  const std::string& text() const { return text_; } // the file's content as of the next flush

private:
  std::filesystem::path path_;
  std::vector<std::string> columns_;
  std::string text_;
  std::size_t row_count_ = 0;
  bool written_ = false;
};

// A value as SeriesCsv writes it.
std::string csv_number(double value);

} // namespace kdem
