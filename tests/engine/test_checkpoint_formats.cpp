// Checkpoints of older formats still restart. Format 1 (written before particles carried sources
// and tags and pairs had several contact slots): a file stripped of what formats 2 to 4 added
// reads back with one slot per pair and entry and no labels, and the run goes on bit for bit as
// the uninterrupted one. Format 2 (before the steps of the Newton warm starts): see below.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
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
  std::vector<const char*> added = {"pairs/separation_expiry", "surface_travel"};
  if (format < 3)
    added.push_back("pairs/midway_step");
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

// An uninterrupted run of a scene and a second engine restarted from its checkpoint after
// `before` steps, turned into one of `format`: both at that step.
struct Restart {
  std::unique_ptr<Engine> straight, restarted;
};

Restart restart_from_format(const SceneConfig& scene, int before, std::int64_t format) {
  Restart r{std::make_unique<Engine>(scene), std::make_unique<Engine>(scene)};
  r.straight->advance(before);
  const std::string path = (std::filesystem::path(::testing::TempDir()) /
                            ("kdem_format_" + std::to_string(format) + ".h5"))
                               .string();
  r.straight->write_checkpoint(path);
  downgrade(path, format);
  r.restarted->read_checkpoint(path);
  std::remove(path.c_str());
  return r;
}

// Both engines advanced by `steps`, the largest difference of a position coordinate.
double largest_difference_after(Restart& r, int steps, bool bit_for_bit) {
  r.straight->advance(steps);
  r.restarted->advance(steps);
  const ParticleSnapshot a = r.straight->snapshot(), b = r.restarted->snapshot();
  EXPECT_EQ(a.id, b.id);
  if (a.id != b.id)
    return std::numeric_limits<double>::infinity();
  if (bit_for_bit) {
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.velocity, b.velocity);
    EXPECT_EQ(a.angular_velocity, b.angular_velocity);
  }
  double largest = 0;
  for (std::size_t k = 0; k < a.position.size(); ++k)
    largest = std::max(largest, std::fabs(a.position[k] - b.position[k]));
  return largest;
}

TEST(CheckpointFormats, AFormatOneCheckpointRestartsBitForBit) {
  Restart r = restart_from_format(testing::cli_scene("small_hopper"), 3000, 1);
  ASSERT_GT(r.straight->diagnostics().pair_contacts, 0) << "the restart must carry history";
  ASSERT_GT(r.straight->diagnostics().wall_contacts, 0);
  const ParticleSnapshot labels = r.restarted->snapshot();
  for (std::size_t i = 0; i < labels.size(); ++i) {
    EXPECT_EQ(labels.source[i], -1) << "format 1 names no source";
    EXPECT_EQ(labels.tag[i], -1);
  }
  largest_difference_after(r, 400, true);
}

// Format 3 added the steps of the Newton warm starts. A format-2 file restarts with every step
// zero: the first starts are the last points themselves, so the run is not bit for bit the
// uninterrupted one, but agrees to what Newton's tolerance leaves (1e-9 m, 1e-6 of a particle
// size, as for runs that differ only in their starts; see test_warm_start_extrapolation.cpp).
TEST(CheckpointFormats, AFormatTwoCheckpointOfSuperquadricsRestartsWithoutSteps) {
  Restart r = restart_from_format(testing::cli_scene("small_superquadrics"), 2500, 2);
  ASSERT_GT(r.straight->diagnostics().pair_contacts, 0) << "the restart must carry warm starts";
  EXPECT_LT(largest_difference_after(r, 500, false), 1e-9);
  EXPECT_EQ(r.straight->diagnostics().pair_contacts, r.restarted->diagnostics().pair_contacts);
  EXPECT_EQ(r.restarted->narrow_phase_totals().failures, 0);
}

// Format 4 added the certificates' expiries and the surface travel. A format-3 file restarts with
// no expiry: each certificate is checked against the bodies until it holds again, and whenever
// the expiry would have held that check holds too (the expiry bounds the same motion more
// loosely), so the same pairs are skipped and the run goes on bit for bit.
TEST(CheckpointFormats, AFormatThreeCheckpointOfSuperquadricsRestartsBitForBit) {
  Restart r = restart_from_format(testing::cli_scene("small_superquadrics"), 2500, 3);
  ASSERT_GT(r.straight->diagnostics().pair_contacts, 0);
  largest_difference_after(r, 500, true);
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
