#pragma once
// A checkpoint held in memory as its datasets, edits to it driven by fuzz input bytes, and the
// HDF5 reading and writing of it (for the checkpoint_reader fuzz target).
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include <hdf5.h>

namespace kdem::fuzz {

struct Dataset {
  enum class Kind { real, int32, int64, uint64, text };
  std::string name;
  Kind kind = Kind::real;
  std::vector<hsize_t> shape;         // {} for a scalar
  std::vector<double> reals;          // Kind::real
  std::vector<std::int64_t> integers; // the integer kinds (uint64 stored bit for bit)
  std::string text;                   // Kind::text

  std::size_t size() const { return kind == Kind::real ? reals.size() : integers.size(); }
};

struct CheckpointImage {
  std::vector<Dataset> datasets; // in name order
};

// Every dataset of the file, with its element kind and shape.
CheckpointImage read_image(const std::string& path);

// Where an input names a dataset: the offset of the two bytes that chose it (an edit's target,
// or the source a copy takes), the dataset chosen, and the names it was chosen among.
struct DatasetChoice {
  std::size_t offset = 0;
  std::string name;
  std::vector<std::string> among;
};

// Reads edits from the bytes until they run out (at most 16): each names a dataset and an
// operation with its operands. Any byte string is a valid list of edits. Returns the names of
// the datasets edited or removed; `choices`, when given, receives each choice of a dataset.
std::set<std::string> apply_edits(CheckpointImage& image, const std::uint8_t* data,
                                  std::size_t size, std::vector<DatasetChoice>* choices = nullptr);

// A dataset is chosen by its index among the image's datasets, so a checkpoint that gains a
// dataset changes what an input written before means. Returns the input rewritten so that each
// edit chooses in `now` the dataset it chose in `before` (the image before the change); the
// operands are left as they are. Throws where `now` lacks a dataset `before` had.
std::vector<std::uint8_t> retarget_edits(const CheckpointImage& before, const CheckpointImage& now,
                                         const std::vector<std::uint8_t>& input);

// The file at base_path (which `image` was read from, before the edits) copied to path, with
// the touched datasets written again as the image holds them, or removed where it has none.
void write_edited(const std::string& base_path, const CheckpointImage& image,
                  const std::set<std::string>& touched, const std::string& path);

} // namespace kdem::fuzz
