// A checkpoint that the engine could not have written is refused with the dataset and the rule
// it breaks, and the engine that tried to read it goes on as if it had not: each test changes one
// value of a real checkpoint (a pair index out of range, a non-finite position, a negative count,
// a table of the wrong width, offsets out of order) and runs the refusing engine on bit for bit
// beside an untouched one. The inputs come from the checkpoint_reader fuzz target's edits
// (tests/fuzz/), made here by hand so that each rule has its own test.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <vector>

#include "checkpoint_test_support.hpp"
#include "scene_builders.hpp"

namespace kdem {
namespace {

// The whole of one dataset, changed by `edit` and written back in place (same size and type).
template <class Value>
void edit_dataset(const std::string& path, const std::string& name, hid_t memory_type,
                  const std::function<void(std::vector<Value>&)>& edit) {
  ASSERT_TRUE(testing::edit_checkpoint_dataset<Value>(path, name, memory_type, edit))
      << name << " of " << path << " is missing, empty or unwritable";
}

// Replaces a dataset by a table of `columns` columns holding the same values where they fit.
void rewrite_with_columns(const std::string& path, const std::string& name, hsize_t columns) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t old = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  const std::vector<double> values = testing::read_whole_dataset<double>(old, H5T_NATIVE_DOUBLE);
  H5Dclose(old);
  H5Ldelete(file, name.c_str(), H5P_DEFAULT);
  const hsize_t dims[2] = {values.size() / columns, columns};
  const hid_t new_space = H5Screate_simple(2, dims, nullptr);
  const hid_t created = H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, new_space, H5P_DEFAULT,
                                   H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(created, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Dclose(created);
  H5Sclose(new_space);
  H5Fclose(file);
}

class CheckpointChecks : public ::testing::Test {
protected:
  // 1500 steps of the small hopper: particles touch each other and the walls, so that the lists
  // carry history (asserted).
  void SetUp() override {
    scene_ = testing::cli_scene("small_hopper");
    untouched_ = std::make_unique<Engine>(scene_);
    refusing_ = std::make_unique<Engine>(scene_);
    untouched_->advance(1500);
    refusing_->advance(1500);
    ASSERT_GT(untouched_->diagnostics().pair_contacts, 0);
    ASSERT_GT(untouched_->diagnostics().wall_contacts, 0);
    path_ = (std::filesystem::path(::testing::TempDir()) / "kdem_checked.h5").string();
    untouched_->write_checkpoint(path_);
  }
  void TearDown() override { std::remove(path_.c_str()); }

  // The checkpoint is refused with a message holding `expected`, and the refusing engine then
  // runs on bit for bit with the untouched one.
  void expect_refused(const std::string& expected) {
    try {
      refusing_->read_checkpoint(path_);
      ADD_FAILURE() << "the checkpoint was read; expected a refusal naming: " << expected;
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path_), std::string::npos) << message;
      EXPECT_NE(message.find(expected), std::string::npos) << message;
    }
    untouched_->advance(200);
    refusing_->advance(200);
    const ParticleSnapshot a = untouched_->snapshot(), b = refusing_->snapshot();
    ASSERT_EQ(a.id, b.id);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.velocity, b.velocity);
    EXPECT_EQ(a.angular_velocity, b.angular_velocity);
    EXPECT_EQ(untouched_->step_count(), refusing_->step_count());
  }

  SceneConfig scene_;
  std::unique_ptr<Engine> untouched_, refusing_;
  std::string path_;
};

TEST_F(CheckpointChecks, TheUntouchedCheckpointIsRead) {
  refusing_->read_checkpoint(path_);
  untouched_->advance(200);
  refusing_->advance(200);
  EXPECT_EQ(untouched_->snapshot().position, refusing_->snapshot().position);
}

TEST_F(CheckpointChecks, APairPartnerOutOfRangeIsRefused) {
  const int particles = untouched_->particle_count();
  edit_dataset<int>(path_, "pairs/pair_j", H5T_NATIVE_INT,
                    [&](std::vector<int>& v) { v.back() = particles; });
  expect_refused("pairs/pair_j row");
}

TEST_F(CheckpointChecks, AWallElementOutOfRangeIsRefused) {
  edit_dataset<int>(path_, "wall_contacts/element", H5T_NATIVE_INT,
                    [&](std::vector<int>& v) { v.front() = -1; });
  expect_refused("wall_contacts/element row 0");
}

TEST_F(CheckpointChecks, ANonFinitePositionIsRefused) {
  edit_dataset<double>(path_, "particles/position", H5T_NATIVE_DOUBLE, [](std::vector<double>& v) {
    v[4] = std::numeric_limits<double>::quiet_NaN();
  });
  expect_refused("particles/position row 1 is not finite");
}

TEST_F(CheckpointChecks, ANegativeParticleCountIsRefused) {
  edit_dataset<std::int64_t>(path_, "particle_count", H5T_NATIVE_INT64,
                             [](std::vector<std::int64_t>& v) { v[0] = -3; });
  expect_refused("particle_count = -3 is not a count");
}

// Found by the checkpoint_reader fuzz target: the engine allocated the entries' results for
// this count (51 GB) before checking it against the tables.
TEST_F(CheckpointChecks, AWallEntryCountBeyondTheTablesIsRefusedBeforeAnythingIsAllocated) {
  edit_dataset<std::int64_t>(path_, "wall_entry_count", H5T_NATIVE_INT64,
                             [](std::vector<std::int64_t>& v) { v[0] = 2147483647; });
  expect_refused("wall_contacts/row_start ends at");
}

// Found by the checkpoint_reader fuzz target (an input that took 2 s under the sanitizers):
// largest_radius set to 0 was taken, and the pair list's cells, sized 2 x largest_radius + skin,
// shrank to the skin: a far larger grid, and pairs within reach but more than one cell apart
// (the search looks at the 27 cells around a particle) missed without an error.
TEST_F(CheckpointChecks, ALargestRadiusBelowAParticlesIsRefused) {
  edit_dataset<double>(path_, "largest_radius", H5T_NATIVE_DOUBLE,
                       [](std::vector<double>& v) { v[0] = 0; });
  expect_refused("largest_radius 0 is below the largest particle radius");
}

TEST_F(CheckpointChecks, ASmallestRadiusAboveAParticlesIsRefused) {
  edit_dataset<double>(path_, "smallest_radius", H5T_NATIVE_DOUBLE,
                       [](std::vector<double>& v) { v[0] = 1; });
  expect_refused("smallest_radius 1 is above the smallest particle radius");
}

TEST_F(CheckpointChecks, AParticleCountOtherThanTheRowsIsRefused) {
  edit_dataset<std::int64_t>(path_, "particle_count", H5T_NATIVE_INT64,
                             [](std::vector<std::int64_t>& v) { v[0] += 1; });
  expect_refused("particle_count differs from the rows of particles/id");
}

// The run increments it: a value near the limit would overflow within the run.
TEST_F(CheckpointChecks, AStepCountNearOverflowIsRefused) {
  edit_dataset<std::int64_t>(path_, "step", H5T_NATIVE_INT64, [](std::vector<std::int64_t>& v) {
    v[0] = std::numeric_limits<std::int64_t>::max();
  });
  expect_refused("step = 9223372036854775807 is not a counter below 2^53");
}

TEST_F(CheckpointChecks, PairOffsetsOutOfOrderAreRefused) {
  edit_dataset<int>(path_, "pairs/row_start", H5T_NATIVE_INT, [](std::vector<int>& v) {
    const std::size_t middle = v.size() / 2;
    v[middle] = v[middle + 1] + 1;
  });
  expect_refused("pairs/row_start decreases");
}

TEST_F(CheckpointChecks, AVelocityTableOfTwoColumnsIsRefused) {
  rewrite_with_columns(path_, "particles/velocity", 2);
  expect_refused("particles/velocity is not a table of 3 column(s)");
}

TEST_F(CheckpointChecks, AnIdGivenTwiceIsRefused) {
  edit_dataset<std::int64_t>(path_, "particles/id", H5T_NATIVE_INT64,
                             [](std::vector<std::int64_t>& v) { v[1] = v[0]; });
  expect_refused("particles/id holds an id twice");
}

} // namespace
} // namespace kdem
