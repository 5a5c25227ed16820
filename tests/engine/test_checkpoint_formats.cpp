// Checkpoints of older formats still restart. Format 1 (written before particles carried sources
// and tags and pairs had several contact slots): a file stripped of what formats 2 and 3 added
// reads back with one slot per pair and entry and no labels, and the run goes on bit for bit as
// the uninterrupted one. Format 2 (before the steps of the Newton warm starts): see below.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "scene_builders.hpp"

namespace kdem {
namespace {

// Overwrites the format number of an open checkpoint.
void write_format(hid_t file, std::int64_t value) {
  const hid_t format = H5Dopen2(file, "format", H5P_DEFAULT);
  ASSERT_GE(format, 0);
  EXPECT_GE(H5Dwrite(format, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value), 0);
  H5Dclose(format);
}

// Turns a checkpoint of the current format into one of an older format in place, removing the
// datasets the later formats added.
void downgrade(const std::string& path, std::int64_t format) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0) << path;
  std::vector<const char*> added = {"pairs/midway_step"};
  if (format < 2)
    added.insert(added.end(),
                 {"particles/source", "particles/tag", "pairs/contact_start", "pairs/feature_i",
                  "pairs/feature_j", "wall_contacts/contact_start", "wall_contacts/feature"});
  for (const char* name : added)
    if (H5Lexists(file, name, H5P_DEFAULT) > 0)
      EXPECT_GE(H5Ldelete(file, name, H5P_DEFAULT), 0) << name;
  write_format(file, format);
  H5Fclose(file);
}

TEST(CheckpointFormats, AFormatOneCheckpointRestartsBitForBit) {
  const SceneConfig scene = testing::cli_scene("small_hopper");
  Engine straight(scene);
  straight.advance(3000);
  ASSERT_GT(straight.diagnostics().pair_contacts, 0) << "the restart must carry contact history";
  ASSERT_GT(straight.diagnostics().wall_contacts, 0);
  const std::string path =
      (std::filesystem::path(::testing::TempDir()) / "kdem_format_1.h5").string();
  straight.write_checkpoint(path);
  downgrade(path, 1);
  Engine restarted(scene);
  restarted.read_checkpoint(path);
  std::remove(path.c_str());
  const ParticleSnapshot labels = restarted.snapshot();
  for (std::size_t i = 0; i < labels.size(); ++i) {
    EXPECT_EQ(labels.source[i], -1) << "format 1 names no source";
    EXPECT_EQ(labels.tag[i], -1);
  }
  straight.advance(400);
  restarted.advance(400);
  const ParticleSnapshot a = straight.snapshot(), b = restarted.snapshot();
  ASSERT_EQ(a.id, b.id);
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.velocity, b.velocity);
  EXPECT_EQ(a.angular_velocity, b.angular_velocity);
}

// Format 3 added the steps of the Newton warm starts. A format-2 file restarts with every step
// zero: the first starts are the last points themselves, so the run is not bit for bit the
// uninterrupted one, but agrees to what Newton's tolerance leaves (1e-9 m, 1e-6 of a particle
// size, as for runs that differ only in their starts; see test_warm_start_extrapolation.cpp).
TEST(CheckpointFormats, AFormatTwoCheckpointOfSuperquadricsRestartsWithoutSteps) {
  const SceneConfig scene = testing::cli_scene("small_superquadrics");
  Engine straight(scene);
  straight.advance(2500);
  ASSERT_GT(straight.diagnostics().pair_contacts, 0) << "the restart must carry warm starts";
  const std::string path =
      (std::filesystem::path(::testing::TempDir()) / "kdem_format_2.h5").string();
  straight.write_checkpoint(path);
  downgrade(path, 2);
  Engine restarted(scene);
  restarted.read_checkpoint(path);
  std::remove(path.c_str());
  straight.advance(500);
  restarted.advance(500);
  const ParticleSnapshot a = straight.snapshot(), b = restarted.snapshot();
  ASSERT_EQ(a.id, b.id);
  double largest = 0;
  for (std::size_t k = 0; k < a.position.size(); ++k)
    largest = std::max(largest, std::fabs(a.position[k] - b.position[k]));
  EXPECT_LT(largest, 1e-9);
  EXPECT_EQ(straight.diagnostics().pair_contacts, restarted.diagnostics().pair_contacts);
  EXPECT_EQ(restarted.narrow_phase_totals().failures, 0);
}

TEST(CheckpointFormats, AnUnknownFormatIsRefused) {
  Engine engine(testing::cli_scene("small_hopper"));
  const std::string path =
      (std::filesystem::path(::testing::TempDir()) / "kdem_format_9.h5").string();
  engine.write_checkpoint(path);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  write_format(file, 9);
  H5Fclose(file);
  Engine restarted(testing::cli_scene("small_hopper"));
  try {
    restarted.read_checkpoint(path);
    ADD_FAILURE() << "a checkpoint of format 9 was read";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("unknown checkpoint format 9"), std::string::npos)
        << e.what();
  }
  std::remove(path.c_str());
}

} // namespace
} // namespace kdem
