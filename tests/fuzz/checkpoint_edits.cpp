#include "checkpoint_edits.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <system_error>

#include "hdf5_io.hpp"

namespace kdem::fuzz {
namespace {

using Kind = Dataset::Kind;

// The input bytes, read front to back; zeros once they run out.
class Bytes {
public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool empty() const { return used_ >= size_; }
  std::size_t offset() const { return used_; }
  std::uint8_t byte() { return empty() ? 0 : data_[used_++]; }
  std::uint64_t word(int bytes) {
    std::uint64_t value = 0;
    for (int k = 0; k < bytes; ++k)
      value = value << 8 | byte();
    return value;
  }

private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t used_ = 0;
};

// Values near the edges of what the reader checks.
constexpr double interesting_reals[] = {0.0,
                                        -0.0,
                                        1.0,
                                        -1.0,
                                        0.5,
                                        1e-12,
                                        1e300,
                                        -1e300,
                                        std::numeric_limits<double>::denorm_min(),
                                        std::numeric_limits<double>::max(),
                                        std::numeric_limits<double>::infinity(),
                                        -std::numeric_limits<double>::infinity(),
                                        std::numeric_limits<double>::quiet_NaN()};
constexpr std::int64_t interesting_integers[] = {0,
                                                 -1,
                                                 1,
                                                 2,
                                                 std::numeric_limits<std::int32_t>::max(),
                                                 std::numeric_limits<std::int32_t>::min(),
                                                 std::numeric_limits<std::int64_t>::max(),
                                                 std::numeric_limits<std::int64_t>::min()};
constexpr std::size_t largest_rows = 4096;

std::size_t columns_of(const Dataset& d) {
  return d.shape.size() == 2 ? d.shape[1] : 1;
}
std::size_t rows_of(const Dataset& d) {
  return d.shape.empty() ? 1 : d.shape[0];
}

double real_from(Bytes& bytes) {
  const std::uint8_t pick = bytes.byte();
  constexpr std::size_t named = std::size(interesting_reals);
  if (pick < 2 * named)
    return interesting_reals[pick % named];
  const std::uint64_t bits = bytes.word(8);
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// An integer near a count the image holds (rows of this dataset), a limit, or any 64 bits.
std::int64_t integer_from(Bytes& bytes, const Dataset& d) {
  const std::uint8_t pick = bytes.byte();
  constexpr std::size_t named = std::size(interesting_integers);
  const auto rows = std::int64_t(rows_of(d));
  if (pick < named)
    return interesting_integers[pick];
  if (pick < named + 3)
    return rows - 1 + (pick - std::int64_t(named));
  return std::int64_t(bytes.word(8));
}

void set_value(Dataset& d, Bytes& bytes) {
  const std::size_t size = d.size();
  const std::size_t at = size == 0 ? 0 : bytes.word(4) % size;
  if (size == 0)
    return;
  if (d.kind == Kind::real)
    d.reals[at] = real_from(bytes);
  else
    d.integers[at] = integer_from(bytes, d);
}

// One element moved by a small step: an index one off, a count one short.
void shift_value(Dataset& d, Bytes& bytes) {
  const std::size_t size = d.size();
  const std::size_t at = size == 0 ? 0 : bytes.word(4) % size;
  const auto step = std::int8_t(bytes.byte());
  if (size == 0)
    return;
  if (d.kind == Kind::real)
    d.reals[at] += step * (d.reals[at] == 0 ? 1.0 : d.reals[at] / 64);
  else
    d.integers[at] =
        std::int64_t(std::uint64_t(d.integers[at]) + std::uint64_t(std::int64_t(step)));
}

template <class Value> void resize_cyclic(std::vector<Value>& values, std::size_t size) {
  const std::size_t old_size = values.size();
  values.resize(size);
  for (std::size_t k = old_size; k < size && old_size > 0; ++k)
    values[k] = values[k % old_size];
}

void resize_values(Dataset& d, std::size_t size) {
  if (d.kind == Kind::real)
    resize_cyclic(d.reals, size);
  else
    resize_cyclic(d.integers, size);
}

void resize_rows(Dataset& d, Bytes& bytes) {
  if (d.kind == Kind::text)
    return;
  const std::size_t rows = rows_of(d), columns = columns_of(d);
  const std::size_t choices[] = {0, rows > 0 ? rows - 1 : 0, rows + 1, 2 * rows};
  const std::uint8_t pick = bytes.byte();
  const std::size_t new_rows =
      std::min(largest_rows, pick < 4 * std::size(choices) ? choices[pick % std::size(choices)]
                                                           : std::size_t(bytes.byte()));
  d.shape = d.shape.size() == 2 ? std::vector<hsize_t>{new_rows, columns}
                                : std::vector<hsize_t>{new_rows};
  resize_values(d, new_rows * columns);
}

void reshape_columns(Dataset& d, Bytes& bytes) {
  if (d.kind == Kind::text)
    return;
  const std::size_t columns = bytes.byte() % 5;
  const std::size_t rows = columns == 0 ? 0 : d.size() / columns;
  d.shape = {rows, columns};
  resize_values(d, rows * columns);
}

void change_kind(Dataset& d, Bytes& bytes) {
  if (d.kind == Kind::text)
    return;
  const Kind kinds[] = {Kind::real, Kind::int32, Kind::int64, Kind::uint64};
  const Kind kind = kinds[bytes.byte() % std::size(kinds)];
  if ((kind == Kind::real) == (d.kind == Kind::real)) {
    d.kind = kind;
    return;
  }
  if (kind == Kind::real) {
    d.reals.assign(d.integers.begin(), d.integers.end());
    d.integers.clear();
  } else {
    for (double value : d.reals)
      d.integers.push_back(std::isfinite(value) && std::abs(value) < 9e18 ? std::int64_t(value)
                                                                          : 0);
    d.reals.clear();
  }
  d.kind = kind;
}

void toggle_scalar(Dataset& d) {
  if (d.kind == Kind::text)
    return;
  if (d.shape.empty()) {
    d.shape = {1, 1};
    return;
  }
  d.shape = {};
  resize_values(d, 1);
  if (d.size() == 0 && d.kind == Kind::real)
    d.reals = {0.0};
  else if (d.size() == 0)
    d.integers = {0};
}

void edit_text(Dataset& d, Bytes& bytes) {
  const std::uint8_t pick = bytes.byte();
  const char c = char(bytes.byte());
  const std::size_t at = d.text.empty() ? 0 : bytes.word(2) % d.text.size();
  if (pick % 3 == 0 || d.text.empty())
    d.text.insert(d.text.begin() + at, c);
  else if (pick % 3 == 1)
    d.text[at] = c;
  else
    d.text.resize(at);
}

std::size_t choose_dataset(const CheckpointImage& image, Bytes& bytes,
                           std::vector<DatasetChoice>* choices) {
  const std::size_t offset = bytes.offset();
  const std::size_t chosen = bytes.word(2) % image.datasets.size();
  if (choices) {
    DatasetChoice choice{offset, image.datasets[chosen].name, {}};
    for (const Dataset& d : image.datasets)
      choice.among.push_back(d.name);
    choices->push_back(std::move(choice));
  }
  return chosen;
}

void apply_edit(CheckpointImage& image, Bytes& bytes, std::set<std::string>& touched,
                std::vector<DatasetChoice>* choices) {
  auto& datasets = image.datasets;
  if (datasets.empty())
    return;
  const std::size_t target = choose_dataset(image, bytes, choices);
  const std::uint8_t operation = bytes.byte() % 9;
  Dataset& d = datasets[target];
  touched.insert(d.name);
  switch (operation) {
  case 0:
    set_value(d, bytes);
    break;
  case 1:
    shift_value(d, bytes);
    break;
  case 2:
    resize_rows(d, bytes);
    break;
  case 3:
    reshape_columns(d, bytes);
    break;
  case 4:
    datasets.erase(datasets.begin() + std::ptrdiff_t(target));
    break;
  case 5:
    change_kind(d, bytes);
    break;
  case 6:
    toggle_scalar(d);
    break;
  case 7: {
    const Dataset& source = datasets[choose_dataset(image, bytes, choices)];
    const std::string name = d.name;
    d = source;
    d.name = name;
    break;
  }
  default:
    if (d.kind == Kind::text)
      edit_text(d, bytes);
    else
      set_value(d, bytes);
  }
}

// ---- HDF5 -------------------------------------------------------------------------------------

herr_t collect_link(hid_t group, const char* name, const H5L_info_t*, void* names) {
  const hid_t object = H5Oopen(group, name, H5P_DEFAULT);
  if (object >= 0) {
    if (H5Iget_type(object) == H5I_DATASET)
      static_cast<std::vector<std::string>*>(names)->push_back(name);
    H5Oclose(object);
  }
  return 0;
}

std::vector<std::string> dataset_names(const std::string& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0)
    throw std::runtime_error(path + ": cannot open");
  std::vector<std::string> names;
  H5Lvisit(file, H5_INDEX_NAME, H5_ITER_INC, collect_link, &names);
  H5Fclose(file);
  return names;
}

Kind kind_of(const std::string& path, const std::string& name) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  const hid_t type = H5Dget_type(dataset);
  Kind kind = Kind::text;
  if (H5Tget_class(type) == H5T_FLOAT)
    kind = Kind::real;
  else if (H5Tget_class(type) == H5T_INTEGER && H5Tget_size(type) == 4)
    kind = Kind::int32;
  else if (H5Tget_class(type) == H5T_INTEGER)
    kind = H5Tget_sign(type) == H5T_SGN_NONE ? Kind::uint64 : Kind::int64;
  H5Tclose(type);
  H5Dclose(dataset);
  H5Fclose(file);
  return kind;
}

Dataset read_dataset(const Hdf5Reader& in, const std::string& name, Kind kind) {
  Dataset d;
  d.name = name;
  d.kind = kind;
  d.shape = in.shape(name);
  switch (kind) {
  case Kind::real:
    d.reals = in.read_doubles(name);
    break;
  case Kind::int32: {
    const auto values = in.read_ints(name);
    d.integers.assign(values.begin(), values.end());
    break;
  }
  case Kind::int64:
    d.integers = in.read_int64(name);
    break;
  case Kind::uint64: {
    const auto values = in.read_uint64(name);
    d.integers.assign(values.begin(), values.end());
    break;
  }
  case Kind::text:
    d.text = in.read_string(name);
    break;
  }
  return d;
}

// The file type of a dataset of this kind, as kdem's Hdf5Writer stores it;
// a text's type is made for its length and closed by the caller.
hid_t file_type_of(const Dataset& d) {
  switch (d.kind) {
  case Kind::real:
    return H5T_IEEE_F64LE;
  case Kind::int32:
    return H5T_STD_I32LE;
  case Kind::int64:
    return H5T_STD_I64LE;
  case Kind::uint64:
    return H5T_STD_U64LE;
  case Kind::text:
    break;
  }
  const hid_t text = H5Tcopy(H5T_C_S1);
  H5Tset_size(text, d.text.empty() ? 1 : d.text.size());
  H5Tset_strpad(text, H5T_STR_NULLPAD);
  H5Tset_cset(text, H5T_CSET_UTF8);
  return text;
}

hid_t dataspace_of(const Dataset& d) {
  if (d.kind == Kind::text)
    return H5Screate(d.text.empty() ? H5S_NULL : H5S_SCALAR);
  if (d.shape.empty())
    return H5Screate(H5S_SCALAR);
  return H5Screate_simple(int(d.shape.size()), d.shape.data(), nullptr);
}

void create_dataset(hid_t file, const Dataset& d) {
  const hid_t type = file_type_of(d), space = dataspace_of(d);
  const hid_t dataset =
      H5Dcreate2(file, d.name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (dataset < 0)
    throw std::runtime_error("cannot create " + d.name);
  const bool any = d.kind == Kind::text ? !d.text.empty() : d.size() > 0;
  herr_t written = 0;
  if (any) {
    switch (d.kind) {
    case Kind::real:
      written = H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.reals.data());
      break;
    case Kind::int32: {
      const std::vector<int> int32s(d.integers.begin(), d.integers.end());
      written = H5Dwrite(dataset, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, int32s.data());
      break;
    }
    case Kind::int64:
    case Kind::uint64: // the same 64 bits
      written = H5Dwrite(dataset, d.kind == Kind::int64 ? H5T_NATIVE_INT64 : H5T_NATIVE_UINT64,
                         H5S_ALL, H5S_ALL, H5P_DEFAULT, d.integers.data());
      break;
    case Kind::text:
      written = H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.text.data());
      break;
    }
  }
  H5Dclose(dataset);
  H5Sclose(space);
  if (d.kind == Kind::text)
    H5Tclose(type);
  if (written < 0)
    throw std::runtime_error("cannot write " + d.name);
}

const Dataset* find(const CheckpointImage& image, const std::string& name) {
  for (const Dataset& d : image.datasets)
    if (d.name == name)
      return &d;
  return nullptr;
}

// libFuzzer's timers interrupt system calls (SIGALRM), and a copy interrupted that way fails
// with EINTR: it is tried again.
void copy_file_retrying(const std::string& from, const std::string& to) {
  for (int attempt = 1;; ++attempt) {
    std::error_code error;
    std::filesystem::copy_file(from, to, std::filesystem::copy_options::overwrite_existing, error);
    if (!error)
      return;
    if (error != std::errc::interrupted || attempt == 100)
      throw std::filesystem::filesystem_error("cannot copy the checkpoint", from, to, error);
  }
}

std::vector<DatasetChoice> choices_of(CheckpointImage image,
                                      const std::vector<std::uint8_t>& input) {
  std::vector<DatasetChoice> choices;
  apply_edits(image, input.data(), input.size(), &choices);
  return choices;
}

} // namespace

CheckpointImage read_image(const std::string& path) {
  CheckpointImage image;
  const Hdf5Reader in(path);
  for (const std::string& name : dataset_names(path))
    image.datasets.push_back(read_dataset(in, name, kind_of(path, name)));
  return image;
}

void write_edited(const std::string& base_path, const CheckpointImage& image,
                  const std::set<std::string>& touched, const std::string& path) {
  copy_file_retrying(base_path, path);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0)
    throw std::runtime_error(path + ": cannot open");
  for (const std::string& name : touched) {
    H5Ldelete(file, name.c_str(), H5P_DEFAULT);
    if (const Dataset* d = find(image, name))
      create_dataset(file, *d);
  }
  H5Fclose(file);
}

std::set<std::string> apply_edits(CheckpointImage& image, const std::uint8_t* data,
                                  std::size_t size, std::vector<DatasetChoice>* choices) {
  Bytes bytes(data, size);
  std::set<std::string> touched;
  for (int edit = 0; edit < 16 && !bytes.empty(); ++edit)
    apply_edit(image, bytes, touched, choices);
  return touched;
}

// Each pass rewrites the first choice that differs (the later choices depend on it: a removal
// changes the names they are chosen among), so that it names the same dataset; the word is its
// index, and the bytes are extended where the choice was read beyond the input's end (as zeros:
// what Bytes gives there), never past the edit that read it.
std::vector<std::uint8_t> retarget_edits(const CheckpointImage& before, const CheckpointImage& now,
                                         const std::vector<std::uint8_t>& input) {
  const std::vector<DatasetChoice> meant = choices_of(before, input);
  std::vector<std::uint8_t> output = input;
  for (std::size_t pass = 0; pass <= meant.size(); ++pass) {
    const std::vector<DatasetChoice> found = choices_of(now, output);
    std::size_t k = 0;
    while (k < meant.size() && k < found.size() && found[k].name == meant[k].name)
      ++k;
    if (k == meant.size())
      return output;
    if (k == found.size())
      throw std::runtime_error("the rewritten input makes fewer edits than the original");
    const auto& among = found[k].among;
    const auto at = std::find(among.begin(), among.end(), meant[k].name);
    if (at == among.end() || among.size() > 0xffff)
      throw std::runtime_error("no dataset " + meant[k].name + " to choose");
    const auto index = std::size_t(at - among.begin());
    const std::size_t offset = found[k].offset;
    if (output.size() < offset + 2)
      output.resize(offset + 2, 0);
    output[offset] = std::uint8_t(index >> 8);
    output[offset + 1] = std::uint8_t(index & 0xff);
  }
  throw std::runtime_error("the choices of datasets did not settle");
}

} // namespace kdem::fuzz
