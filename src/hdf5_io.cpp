#include "hdf5_io.hpp"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <functional>
#include <numeric>
#include <utility>

#include "atomic_file.hpp"

namespace kdem {

namespace fs = std::filesystem;

namespace {

// Closes an HDF5 identifier when it goes out of scope.
class Handle {
public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) {
      close_(id_);
    }
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// Stops HDF5 from printing its error stack to stderr while this object lives; failures are
// reported by our exceptions instead, which quote the innermost HDF5 message.
class ErrorPrintingSilenced {
public:
  ErrorPrintingSilenced() {
    H5Eget_auto2(H5E_DEFAULT, &saved_function_, &saved_data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~ErrorPrintingSilenced() { H5Eset_auto2(H5E_DEFAULT, saved_function_, saved_data_); }
  ErrorPrintingSilenced(const ErrorPrintingSilenced&) = delete;
  ErrorPrintingSilenced& operator=(const ErrorPrintingSilenced&) = delete;

private:
  H5E_auto2_t saved_function_ = nullptr;
  void* saved_data_ = nullptr;
};

herr_t keep_innermost_description(unsigned depth, const H5E_error2_t* entry, void* text) {
  if (depth == 0 && entry->desc != nullptr) {
    *static_cast<std::string*>(text) = entry->desc;
  }
  return 0;
}

// The innermost message on HDF5's error stack, as ": message", or "" when there is none.
std::string hdf5_error_detail() {
  std::string innermost;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, keep_innermost_description, &innermost);
  H5Eclear2(H5E_DEFAULT);
  return innermost.empty() ? "" : " (HDF5: " + innermost + ")";
}

std::string file_error_text(const fs::path& path, const std::string& name,
                            const std::string& reason) {
  return "HDF5 file '" + path.string() + "', dataset '" + name + "': " + reason;
}

hsize_t element_count(const std::vector<hsize_t>& shape) {
  return std::accumulate(shape.begin(), shape.end(), hsize_t{1}, std::multiplies<hsize_t>());
}

std::string shape_text(const std::vector<hsize_t>& shape) {
  std::string text = "{";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    text += (i == 0 ? "" : ", ") + std::to_string(shape[i]);
  }
  return text + "}";
}

std::string type_description(H5T_class_t type_class, std::size_t size, H5T_sign_t sign) {
  const std::string bits = std::to_string(8 * size) + "-bit ";
  switch (type_class) {
  case H5T_FLOAT:
    return bits + "floating point";
  case H5T_INTEGER:
    return bits + (sign == H5T_SGN_NONE ? "unsigned integer" : "signed integer");
  case H5T_STRING:
    return "string";
  default:
    return "HDF5 type class " + std::to_string(static_cast<int>(type_class));
  }
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Hdf5Writer

Hdf5Writer::Hdf5Writer(fs::path path)
    : path_(std::move(path)), temporary_path_(temporary_path_for(path_)),
      uncaught_exceptions_at_construction_(std::uncaught_exceptions()) {
  ErrorPrintingSilenced silenced;
  file_ = H5Fcreate(temporary_path_.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0) {
    throw std::runtime_error("cannot write HDF5 file '" + path_.string() +
                             "': cannot create temporary file '" + temporary_path_.string() + "'" +
                             hdf5_error_detail());
  }
}

Hdf5Writer::~Hdf5Writer() {
  if (file_ < 0) {
    return;
  }
  if (std::uncaught_exceptions() > uncaught_exceptions_at_construction_) {
    discard();
    return;
  }
  try {
    close();
  } catch (const std::exception& failure) {
    std::fprintf(stderr, "kdem: %s\n", failure.what());
  }
}

hid_t Hdf5Writer::file() const {
  if (file_ < 0) {
    throw std::logic_error("HDF5 file '" + path_.string() + "' is already closed");
  }
  return file_;
}

void Hdf5Writer::write_dataset(const std::string& name, hid_t file_type, hid_t memory_type,
                               hid_t dataspace, const void* data) {
  if (name.empty()) {
    throw std::invalid_argument(file_error_text(path_, name, "empty dataset name"));
  }
  ErrorPrintingSilenced silenced;
  Handle link_properties(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(link_properties.get(), 1);
  Handle dataset(H5Dcreate2(file(), name.c_str(), file_type, dataspace, link_properties.get(),
                            H5P_DEFAULT, H5P_DEFAULT),
                 H5Dclose);
  if (!dataset.valid()) {
    throw std::runtime_error(
        file_error_text(path_, name, "cannot create dataset" + hdf5_error_detail()));
  }
  const bool has_elements = H5Sget_simple_extent_npoints(dataspace) > 0;
  if (has_elements &&
      H5Dwrite(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
    throw std::runtime_error(
        file_error_text(path_, name, "cannot write dataset" + hdf5_error_detail()));
  }
}

template <class Value>
void Hdf5Writer::write_array(const std::string& name, const std::vector<Value>& values,
                             std::vector<hsize_t> shape, hid_t file_type, hid_t memory_type) {
  if (shape.empty()) {
    shape = {static_cast<hsize_t>(values.size())};
  }
  if (element_count(shape) != values.size()) {
    throw std::invalid_argument(file_error_text(path_, name,
                                                "shape " + shape_text(shape) + " does not hold " +
                                                    std::to_string(values.size()) + " values"));
  }
  Handle dataspace(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr),
                   H5Sclose);
  write_dataset(name, file_type, memory_type, dataspace.get(), values.data());
}

void Hdf5Writer::write(const std::string& name, const std::vector<double>& values,
                       std::vector<hsize_t> shape) {
  write_array(name, values, std::move(shape), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
}

void Hdf5Writer::write(const std::string& name, const std::vector<int>& values,
                       std::vector<hsize_t> shape) {
  write_array(name, values, std::move(shape), H5T_STD_I32LE, H5T_NATIVE_INT);
}

void Hdf5Writer::write(const std::string& name, const std::vector<std::int64_t>& values,
                       std::vector<hsize_t> shape) {
  write_array(name, values, std::move(shape), H5T_STD_I64LE, H5T_NATIVE_INT64);
}

void Hdf5Writer::write(const std::string& name, const std::vector<std::uint64_t>& values,
                       std::vector<hsize_t> shape) {
  write_array(name, values, std::move(shape), H5T_STD_U64LE, H5T_NATIVE_UINT64);
}

void Hdf5Writer::write_scalar(const std::string& name, double value) {
  Handle dataspace(H5Screate(H5S_SCALAR), H5Sclose);
  write_dataset(name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, dataspace.get(), &value);
}

void Hdf5Writer::write_scalar(const std::string& name, std::int64_t value) {
  Handle dataspace(H5Screate(H5S_SCALAR), H5Sclose);
  write_dataset(name, H5T_STD_I64LE, H5T_NATIVE_INT64, dataspace.get(), &value);
}

void Hdf5Writer::write_scalar(const std::string& name, std::uint64_t value) {
  Handle dataspace(H5Screate(H5S_SCALAR), H5Sclose);
  write_dataset(name, H5T_STD_U64LE, H5T_NATIVE_UINT64, dataspace.get(), &value);
}

void Hdf5Writer::write_scalar(const std::string& name, int value) {
  write_scalar(name, static_cast<std::int64_t>(value));
}

// A fixed-length, null-padded UTF-8 string of exactly value.size() bytes, so that any bytes
// (embedded or trailing NULs included) read back unchanged. HDF5 has no zero-length string
// type: the empty string is stored with an empty (H5S_NULL) dataspace.
void Hdf5Writer::write_string(const std::string& name, const std::string& value) {
  Handle string_type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(string_type.get(), value.empty() ? 1 : value.size());
  H5Tset_strpad(string_type.get(), H5T_STR_NULLPAD);
  H5Tset_cset(string_type.get(), H5T_CSET_UTF8);
  Handle dataspace(H5Screate(value.empty() ? H5S_NULL : H5S_SCALAR), H5Sclose);
  write_dataset(name, string_type.get(), string_type.get(), dataspace.get(), value.data());
}

void Hdf5Writer::close() {
  if (file_ < 0) {
    return;
  }
  ErrorPrintingSilenced silenced;
  const herr_t status = H5Fclose(file_);
  file_ = H5I_INVALID_HID;
  if (status < 0) {
    const std::string detail = hdf5_error_detail();
    std::error_code ignored;
    fs::remove(temporary_path_, ignored);
    throw std::runtime_error("cannot write HDF5 file '" + path_.string() + "': closing '" +
                             temporary_path_.string() + "' failed" + detail);
  }
  commit_temporary(temporary_path_, path_);
}

void Hdf5Writer::discard() {
  if (file_ >= 0) {
    ErrorPrintingSilenced silenced;
    H5Fclose(file_);
    file_ = H5I_INVALID_HID;
  }
  std::error_code ignored;
  fs::remove(temporary_path_, ignored);
}

// ---------------------------------------------------------------------------------------------
// Hdf5Reader

Hdf5Reader::Hdf5Reader(fs::path path) : path_(std::move(path)) {
  ErrorPrintingSilenced silenced;
  file_ = H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file_ < 0) {
    throw std::runtime_error("cannot open HDF5 file '" + path_.string() + "'" +
                             hdf5_error_detail());
  }
}

Hdf5Reader::~Hdf5Reader() {
  if (file_ >= 0) {
    H5Fclose(file_);
  }
}

std::runtime_error Hdf5Reader::error(const std::string& name, const std::string& reason) const {
  return std::runtime_error(file_error_text(path_, name, reason));
}

bool Hdf5Reader::has(const std::string& name) const {
  ErrorPrintingSilenced silenced;
  // H5Lexists fails, rather than answering false, when an intermediate group is missing:
  // check each prefix of the path in turn.
  std::string prefix;
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t end = std::min(name.find('/', start), name.size());
    if (end > start) {
      prefix += "/" + name.substr(start, end - start);
      if (H5Lexists(file_, prefix.c_str(), H5P_DEFAULT) <= 0) {
        H5Eclear2(H5E_DEFAULT);
        return false;
      }
    }
    start = end + 1;
  }
  if (prefix.empty()) {
    return true; // the root group
  }
  const htri_t object_exists = H5Oexists_by_name(file_, prefix.c_str(), H5P_DEFAULT);
  H5Eclear2(H5E_DEFAULT);
  return object_exists > 0;
}

hid_t Hdf5Reader::open_dataset(const std::string& name) const {
  // Opened straight away (a missing path fails cleanly); the path is walked only to say why
  // an open failed, which costs several lookups per dataset.
  {
    ErrorPrintingSilenced silenced;
    const hid_t dataset = H5Dopen2(file_, name.c_str(), H5P_DEFAULT);
    if (dataset >= 0) {
      return dataset;
    }
    H5Eclear2(H5E_DEFAULT);
  }
  if (!has(name)) {
    throw error(name, "no such dataset");
  }
  ErrorPrintingSilenced silenced;
  const hid_t dataset = H5Dopen2(file_, name.c_str(), H5P_DEFAULT);
  if (dataset < 0) {
    throw error(name, "cannot open as a dataset" + hdf5_error_detail());
  }
  return dataset;
}

namespace {

std::vector<hsize_t> dimensions_of(hid_t dataspace) {
  if (H5Sget_simple_extent_type(dataspace) == H5S_NULL) {
    return {0};
  }
  std::vector<hsize_t> dimensions(
      static_cast<std::size_t>(std::max(0, H5Sget_simple_extent_ndims(dataspace))));
  H5Sget_simple_extent_dims(dataspace, dimensions.data(), nullptr);
  return dimensions;
}

} // namespace

std::vector<hsize_t> Hdf5Reader::shape(const std::string& name) const {
  Handle dataset(open_dataset(name), H5Dclose);
  Handle dataspace(H5Dget_space(dataset.get()), H5Sclose);
  return dimensions_of(dataspace.get());
}

template <class Value>
std::vector<Value> Hdf5Reader::read_array(const std::string& name, H5T_class_t expected_class,
                                          std::size_t expected_size, H5T_sign_t expected_sign,
                                          hid_t memory_type, const char* type_name,
                                          std::vector<hsize_t>* shape) const {
  Handle dataset(open_dataset(name), H5Dclose);
  ErrorPrintingSilenced silenced;
  Handle stored_type(H5Dget_type(dataset.get()), H5Tclose);
  const H5T_class_t stored_class = H5Tget_class(stored_type.get());
  const std::size_t stored_size = H5Tget_size(stored_type.get());
  const H5T_sign_t stored_sign =
      stored_class == H5T_INTEGER ? H5Tget_sign(stored_type.get()) : H5T_SGN_ERROR;
  if (stored_class != expected_class || stored_size != expected_size ||
      stored_sign != expected_sign) {
    throw error(name, "holds " + type_description(stored_class, stored_size, stored_sign) +
                          " values, not " + type_name);
  }
  Handle dataspace(H5Dget_space(dataset.get()), H5Sclose);
  if (shape) {
    *shape = dimensions_of(dataspace.get());
  }
  const hssize_t count = H5Sget_simple_extent_npoints(dataspace.get());
  std::vector<Value> values(static_cast<std::size_t>(std::max<hssize_t>(0, count)));
  if (!values.empty() &&
      H5Dread(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
    throw error(name, "cannot read dataset" + hdf5_error_detail());
  }
  return values;
}

std::vector<double> Hdf5Reader::read_doubles(const std::string& name,
                                             std::vector<hsize_t>* shape) const {
  return read_array<double>(name, H5T_FLOAT, 8, H5T_SGN_ERROR, H5T_NATIVE_DOUBLE,
                            "64-bit floating point", shape);
}

std::vector<int> Hdf5Reader::read_ints(const std::string& name, std::vector<hsize_t>* shape) const {
  return read_array<int>(name, H5T_INTEGER, 4, H5T_SGN_2, H5T_NATIVE_INT, "32-bit signed integer",
                         shape);
}

std::vector<std::int64_t> Hdf5Reader::read_int64(const std::string& name,
                                                 std::vector<hsize_t>* shape) const {
  return read_array<std::int64_t>(name, H5T_INTEGER, 8, H5T_SGN_2, H5T_NATIVE_INT64,
                                  "64-bit signed integer", shape);
}

std::vector<std::uint64_t> Hdf5Reader::read_uint64(const std::string& name) const {
  return read_array<std::uint64_t>(name, H5T_INTEGER, 8, H5T_SGN_NONE, H5T_NATIVE_UINT64,
                                   "64-bit unsigned integer", nullptr);
}

template <class Value>
Value Hdf5Reader::single_value(const std::string& name, std::vector<Value> values) const {
  if (values.size() != 1) {
    throw error(name, "holds " + std::to_string(values.size()) + " values, expected one");
  }
  return values.front();
}

double Hdf5Reader::read_scalar_double(const std::string& name) const {
  return single_value(name, read_doubles(name));
}

std::int64_t Hdf5Reader::read_scalar_int64(const std::string& name) const {
  return single_value(name, read_int64(name));
}

std::uint64_t Hdf5Reader::read_scalar_uint64(const std::string& name) const {
  return single_value(name, read_uint64(name));
}

std::string Hdf5Reader::read_string(const std::string& name) const {
  Handle dataset(open_dataset(name), H5Dclose);
  ErrorPrintingSilenced silenced;
  Handle stored_type(H5Dget_type(dataset.get()), H5Tclose);
  if (H5Tget_class(stored_type.get()) != H5T_STRING) {
    throw error(name, "does not hold a string");
  }
  if (H5Tis_variable_str(stored_type.get()) > 0) {
    throw error(name, "holds a variable-length string; only fixed-length strings are read");
  }
  Handle dataspace(H5Dget_space(dataset.get()), H5Sclose);
  if (H5Sget_simple_extent_type(dataspace.get()) == H5S_NULL) {
    return "";
  }
  if (H5Sget_simple_extent_npoints(dataspace.get()) != 1) {
    throw error(name, "holds more than one string");
  }
  std::string value(H5Tget_size(stored_type.get()), '\0');
  if (H5Dread(dataset.get(), stored_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, value.data()) < 0) {
    throw error(name, "cannot read string" + hdf5_error_detail());
  }
  if (H5Tget_strpad(stored_type.get()) == H5T_STR_NULLTERM) {
    value.resize(value.find('\0') == std::string::npos ? value.size() : value.find('\0'));
  }
  return value;
}

} // namespace kdem
