#pragma once
// A small HDF5 layer for checkpoints and bulk output. Datasets are named by '/'-separated paths
// ("particles/position"); intermediate groups are created on write. Doubles are stored as IEEE
// binary64 and read back bit for bit (NaN payloads, -0.0 and subnormals included). Every error
// is a std::runtime_error naming the file and the dataset.
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <hdf5.h>

namespace kdem {

// Writes a new HDF5 file under a temporary name beside path; close() (or the destructor, when
// no exception is unwinding through it) renames it to path. A writer destroyed during stack
// unwinding removes its temporary file, so path is never left half-written.
class Hdf5Writer {
public:
  explicit Hdf5Writer(std::filesystem::path path);
  ~Hdf5Writer();
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  // An empty shape means one dimension of values.size(); otherwise the product of shape must
  // equal values.size() (row-major, e.g. {N, 3} for positions).
  void write(const std::string& name, const std::vector<double>& values,
             std::vector<hsize_t> shape = {});
  void write(const std::string& name, const std::vector<int>& values,
             std::vector<hsize_t> shape = {});
  void write(const std::string& name, const std::vector<std::int64_t>& values,
             std::vector<hsize_t> shape = {});
  void write(const std::string& name, const std::vector<std::uint64_t>& values,
             std::vector<hsize_t> shape = {});

  // Scalar datasets; an int is stored as a 64-bit signed integer.
  void write_scalar(const std::string& name, double value);
  void write_scalar(const std::string& name, std::int64_t value);
  void write_scalar(const std::string& name, std::uint64_t value);
  void write_scalar(const std::string& name, int value);
  void write_string(const std::string& name, const std::string& value);

  void close();   // flushes, closes and renames to path(); throws on failure
  void discard(); // closes and removes the temporary file; never throws
  const std::filesystem::path& path() const { return path_; }

private:
  template <class Value>
  void write_array(const std::string& name, const std::vector<Value>& values,
                   std::vector<hsize_t> shape, hid_t file_type, hid_t memory_type);
  void write_dataset(const std::string& name, hid_t file_type, hid_t memory_type, hid_t dataspace,
                     const void* data);
  hid_t file() const;

  std::filesystem::path path_;
  std::filesystem::path temporary_path_;
  hid_t file_ = H5I_INVALID_HID;
  int uncaught_exceptions_at_construction_;
};

class Hdf5Reader {
public:
  explicit Hdf5Reader(std::filesystem::path path);
  ~Hdf5Reader();
  Hdf5Reader(const Hdf5Reader&) = delete;
  Hdf5Reader& operator=(const Hdf5Reader&) = delete;

  bool has(const std::string& name) const;                   // a dataset or group at this path
  std::vector<hsize_t> shape(const std::string& name) const; // {} for a scalar

  // Element types must match what the Writer stores: 64-bit float, 32-bit signed, 64-bit
  // signed, 64-bit unsigned integers. A scalar reads as a one-element vector. With `shape`,
  // also the dataset's shape (as shape() gives it), from the same open.
  std::vector<double> read_doubles(const std::string& name,
                                   std::vector<hsize_t>* shape = nullptr) const;
  std::vector<int> read_ints(const std::string& name, std::vector<hsize_t>* shape = nullptr) const;
  std::vector<std::int64_t> read_int64(const std::string& name,
                                       std::vector<hsize_t>* shape = nullptr) const;
  std::vector<std::uint64_t> read_uint64(const std::string& name) const;

  // A dataset holding exactly one value (a scalar, or an array of one element).
  double read_scalar_double(const std::string& name) const;
  std::int64_t read_scalar_int64(const std::string& name) const;
  std::uint64_t read_scalar_uint64(const std::string& name) const;
  std::string read_string(const std::string& name) const;

  const std::filesystem::path& path() const { return path_; }

private:
  template <class Value>
  std::vector<Value> read_array(const std::string& name, H5T_class_t expected_class,
                                std::size_t expected_size, H5T_sign_t expected_sign,
                                hid_t memory_type, const char* type_name,
                                std::vector<hsize_t>* shape) const;
  template <class Value>
  Value single_value(const std::string& name, std::vector<Value> values) const;
  hid_t open_dataset(const std::string& name) const;
  std::runtime_error error(const std::string& name, const std::string& reason) const;

  std::filesystem::path path_;
  hid_t file_ = H5I_INVALID_HID;
};

} // namespace kdem
