#include "series_csv.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>

#include "atomic_file.hpp"

namespace kdem {

namespace {

// RFC 4180: a field holding a comma, quote or line break is quoted, quotes doubled.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) {
    return text;
  }
  std::string quoted = "\"";
  for (const char c : text) {
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  }
  return quoted + "\"";
}

std::string header_line(const std::vector<std::string>& columns) {
  std::string line;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    line += (i == 0 ? "" : ",") + csv_field(columns[i]);
  }
  return line + "\n";
}

} // namespace

std::string csv_number(double value) {
  if (std::isnan(value)) {
    return "nan"; // never "-nan"
  }
  if (std::isinf(value)) {
    return value > 0 ? "inf" : "-inf";
  }
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

SeriesCsv::SeriesCsv(std::filesystem::path path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {
  if (columns_.empty()) {
    throw std::invalid_argument("CSV file '" + path_.string() + "': no columns");
  }
  text_ = header_line(columns_);
}

SeriesCsv::~SeriesCsv() {
  try {
    flush();
  } catch (const std::exception& failure) {
    std::fprintf(stderr, "kdem: %s\n", failure.what());
  }
}

void SeriesCsv::add_row(const std::vector<double>& values) {
  if (values.size() != columns_.size()) {
    throw std::invalid_argument("CSV file '" + path_.string() + "': row of " +
                                std::to_string(values.size()) + " values for " +
                                std::to_string(columns_.size()) + " columns");
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    text_ += (i == 0 ? "" : ",") + csv_number(values[i]);
  }
  text_ += "\n";
  ++row_count_;
  written_ = false;
}

void SeriesCsv::flush() {
  if (written_) {
    return;
  }
  write_text_atomically(path_, text_);
  written_ = true;
}

} // namespace kdem
