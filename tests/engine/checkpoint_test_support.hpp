#pragma once
// Reading datasets of a checkpoint file in tests (the engine's own reader checks and loads a
// whole checkpoint; tests look at or change single datasets).
#include <hdf5.h>

#include <string>
#include <vector>

namespace kdem::testing {

// Every value of an open dataset, read as memory_type; empty where it cannot be read.
template <class Value> std::vector<Value> read_whole_dataset(hid_t dataset, hid_t memory_type) {
  const hid_t space = H5Dget_space(dataset);
  std::vector<Value> values(std::size_t(H5Sget_simple_extent_npoints(space)));
  H5Sclose(space);
  if (H5Dread(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
    values.clear();
  return values;
}

// Every value of dataset `name` of the checkpoint at `path`; empty where it cannot be read.
template <class Value>
std::vector<Value> read_checkpoint_dataset(const std::string& path, const std::string& name,
                                           hid_t memory_type) {
  std::vector<Value> values;
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0)
    return values;
  const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (dataset >= 0) {
    values = read_whole_dataset<Value>(dataset, memory_type);
    H5Dclose(dataset);
  }
  H5Fclose(file);
  return values;
}

// The whole of one dataset, changed by `edit` and written back in place (same size and type);
// false where the file or dataset cannot be opened, read or written.
template <class Value, class Edit>
bool edit_checkpoint_dataset(const std::string& path, const std::string& name, hid_t memory_type,
                             Edit&& edit) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0)
    return false;
  const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  bool written = false;
  if (dataset >= 0) {
    std::vector<Value> values = read_whole_dataset<Value>(dataset, memory_type);
    if (!values.empty()) {
      edit(values);
      written = H5Dwrite(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0;
    }
    H5Dclose(dataset);
  }
  H5Fclose(file);
  return written;
}

} // namespace kdem::testing
