// Scene-file loading: a full scene lands in the right fields; every kind of bad input is refused
// with a message naming the file, line, key path and what was expected.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "src/clump_scene.hpp"
#include "src/dilated_polyhedron_scene.hpp"
#include "src/level_set_scene.hpp"
#include "src/poly_superquadric_scene.hpp"
#include "src/scene_loader.hpp"
#include "src/superquadric_scene.hpp"

namespace {

namespace fs = std::filesystem;
using kdem::SceneConfig;
using kdem::SceneError;

// A folder of its own for files a test writes; removed afterwards.
class ScratchFolder {
public:
  ScratchFolder() {
    const auto* test = testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::path(testing::TempDir()) /
            (std::string("kdem_scene_") + test->test_suite_name() + "_" + test->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchFolder() { fs::remove_all(path_); }

  const fs::path& path() const { return path_; }

  fs::path write(const std::string& name, const std::string& contents) const {
    const fs::path file = path_ / name;
    fs::create_directories(file.parent_path());
    std::ofstream(file) << contents;
    return file;
  }

private:
  fs::path path_;
};

SceneConfig load_text(const std::string& yaml, const std::string& base_dir = ".") {
  return kdem::load_scene_from_string(yaml, "scene.yaml", base_dir);
}

// Succeeds when loading `yaml` throws a SceneError whose message starts with
// "scene.yaml:LINE:", names `key_path` and contains `expectation`.
testing::AssertionResult fails_with(const std::string& yaml, int line, const std::string& key_path,
                                    const std::string& expectation,
                                    const std::string& base_dir = ".") {
  std::string message;
  try {
    load_text(yaml, base_dir);
    return testing::AssertionFailure() << "the scene was accepted";
  } catch (const SceneError& error) {
    message = error.what();
  }
  const std::string position = "scene.yaml:" + std::to_string(line) + ":";
  if (message.rfind(position, 0) != 0)
    return testing::AssertionFailure() << "no \"" << position << "\" at the start of: " << message;
  if (message.find(" " + key_path + ": ") == std::string::npos)
    return testing::AssertionFailure() << "no key path \"" << key_path << "\" in: " << message;
  if (message.find(expectation) == std::string::npos)
    return testing::AssertionFailure() << "no \"" << expectation << "\" in: " << message;
  return testing::AssertionSuccess();
}

// A small valid scene; tests change one line or append lines (numbered from 14).
const std::vector<std::string> minimal_lines{
    "time_step: 1.0e-5",                                         // 1
    "duration: 0.5",                                             // 2
    "materials:",                                                // 3
    "  - name: glass",                                           // 4
    "    density: 2500",                                         // 5
    "    youngs_modulus: 1.0e7",                                 // 6
    "    poisson_ratio: 0.25",                                   // 7
    "particles:",                                                // 8
    "  - name: beads",                                           // 9
    "    material: glass",                                       // 10
    "    size: {radius: 0.002}",                                 // 11
    "    region: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}}", // 12
    "    count: 100",                                            // 13
};

std::string join_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& line : lines)
    text += line + "\n";
  return text;
}

std::string minimal_scene() {
  return join_lines(minimal_lines);
}

// The minimal scene with line `line_number` (1-based) replaced by `replacement`.
std::string minimal_scene_with(int line_number, const std::string& replacement) {
  std::vector<std::string> lines = minimal_lines;
  lines.at(line_number - 1) = replacement;
  return join_lines(lines);
}

// The minimal scene followed by `extra` (its first line is line 14).
std::string minimal_scene_plus(const std::string& extra) {
  return minimal_scene() + extra;
}

const std::string full_scene = R"(# hopper discharge
time_step: 2.0e-6
duration: 1.5
gravity: [0, -9.8, 0]
skin: 0.0004
domain: {min: [-1, -1, -1], max: [1, 1, 2]}
materials:
  - name: glass
    density: 2500
    youngs_modulus: 5.0e7
    poisson_ratio: 0.22
    restitution: 0.9
    friction: 0.3
    rolling_friction: 0.01
  - name: steel
    density: 7800
    youngs_modulus: 2.0e8
    poisson_ratio: 0.3
interactions:
  - materials: [glass, steel]
    friction: 0.4
  - materials: [steel, steel]
    restitution: 0.6
    friction: 0.2
    rolling_friction: 0.02
particles:
  - name: fines
    material: glass
    size: {distribution: uniform, min_radius: 0.001, max_radius: 0.002}
    region: {box: {min: [-0.1, -0.1, 0.5], max: [0.1, 0.1, 0.9]}}
    count: 1e4
    random_orientation: false
    velocity: [0, 0, -1]
    seed: 42
    rate: 5000
    start: 0.1
    interval: 0.02
  - name: mix
    material: steel
    size:
      distribution: discrete
      radii: [0.003, 0.005]
      mass_fractions: [0.25, 0.75]
    region: {cylinder: {base_center: [0, 0, 1], radius: 0.2, height: 0.3}}
    volume_fraction: 0.3
  - name: bell
    material: glass
    size: {distribution: gaussian, mean_radius: 0.004, std_radius: 0.0005,
           min_radius: 0.003, max_radius: 0.005}
    region: {box: {min: [0.5, 0.5, 0.5], max: [0.9, 0.9, 0.9]}}
    count: 20
walls:
  - name: floor
    material: steel
    plane: {point: [0, 0, -0.5], normal: [0, 0, 2]}
  - name: bin
    material: steel
    box: {min: [-1, -1, -1], max: [1, 1, 2], open_faces: [zmax, xmin]}
  - name: drum
    material: steel
    cylinder: {base_center: [0, 0, 0], axis: [3, 0, 4], radius: 0.5, length: 0.25}
    motion: {velocity: [0.1, 0, 0], axis_point: [0, 0, 0.1], axis: [0, 2, 0], rpm: 30, start: 0.2}
  - name: funnel
    material: glass
    mesh: {file: meshes/funnel.stl, scale: 0.001, translate: [0, 0, 0.3]}
    active_from: 0.1
    active_until: 0.75
outlets:
  - name: exit
    box: {min: [-0.05, -0.05, -1], max: [0.05, 0.05, -0.9]}
output:
  directory: results/hopper
  frame_interval: 0.01
  series_interval: 0.001
  checkpoint_interval: 0.5
  final_checkpoint: false
)";

void expect_vector(const kdem::Vec3d& actual, const kdem::Vec3d& expected) {
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(actual[axis], expected[axis], 1e-12) << "component " << axis;
}

// ---- a valid scene -----------------------------------------------------------------------------

class FullScene : public testing::Test {
protected:
  void SetUp() override {
    folder.write("meshes/funnel.stl", "solid funnel\nendsolid funnel\n");
    scene = load_text(full_scene, folder.path().string());
  }
  ScratchFolder folder;
  SceneConfig scene;
};

TEST_F(FullScene, TopLevelValues) {
  EXPECT_EQ(scene.source_file, "scene.yaml");
  EXPECT_DOUBLE_EQ(scene.time_step, 2.0e-6);
  EXPECT_DOUBLE_EQ(scene.duration, 1.5);
  expect_vector(scene.gravity, {0, -9.8, 0});
  EXPECT_DOUBLE_EQ(scene.skin, 0.0004);
  EXPECT_TRUE(scene.has_domain);
  expect_vector(scene.domain_min, {-1, -1, -1});
  expect_vector(scene.domain_max, {1, 1, 2});
}

TEST_F(FullScene, Materials) {
  ASSERT_EQ(scene.materials.size(), 2u);
  const auto& glass = scene.materials[0];
  EXPECT_EQ(glass.name, "glass");
  EXPECT_DOUBLE_EQ(glass.density, 2500);
  EXPECT_DOUBLE_EQ(glass.youngs_modulus, 5.0e7);
  EXPECT_DOUBLE_EQ(glass.poisson_ratio, 0.22);
  EXPECT_DOUBLE_EQ(glass.restitution, 0.9);
  EXPECT_DOUBLE_EQ(glass.friction, 0.3);
  EXPECT_DOUBLE_EQ(glass.rolling_friction, 0.01);
  const auto& steel = scene.materials[1];
  EXPECT_EQ(steel.name, "steel");
  EXPECT_DOUBLE_EQ(steel.restitution, 0.5);
  EXPECT_DOUBLE_EQ(steel.friction, 0.5);
  EXPECT_DOUBLE_EQ(steel.rolling_friction, 0);
}

TEST_F(FullScene, InteractionsFillUnsetValuesWithTheMaterialMean) {
  ASSERT_EQ(scene.interactions.size(), 2u);
  const auto& glass_steel = scene.interactions[0];
  EXPECT_EQ(glass_steel.material_a, "glass");
  EXPECT_EQ(glass_steel.material_b, "steel");
  EXPECT_DOUBLE_EQ(glass_steel.friction, 0.4);
  EXPECT_DOUBLE_EQ(glass_steel.restitution, 0.5 * (0.9 + 0.5));
  EXPECT_DOUBLE_EQ(glass_steel.rolling_friction, 0.5 * (0.01 + 0));
  const auto& steel_steel = scene.interactions[1];
  EXPECT_EQ(steel_steel.material_a, "steel");
  EXPECT_EQ(steel_steel.material_b, "steel");
  EXPECT_DOUBLE_EQ(steel_steel.restitution, 0.6);
  EXPECT_DOUBLE_EQ(steel_steel.friction, 0.2);
  EXPECT_DOUBLE_EQ(steel_steel.rolling_friction, 0.02);
}

TEST_F(FullScene, UniformSourceInABox) {
  ASSERT_EQ(scene.sources.size(), 3u);
  const auto& fines = scene.sources[0];
  EXPECT_EQ(fines.name, "fines");
  EXPECT_EQ(fines.material, "glass");
  EXPECT_EQ(fines.sizes.kind, kdem::SizeDistributionConfig::Kind::Uniform);
  EXPECT_DOUBLE_EQ(fines.sizes.min_radius, 0.001);
  EXPECT_DOUBLE_EQ(fines.sizes.max_radius, 0.002);
  EXPECT_EQ(fines.region.kind, kdem::RegionConfig::Kind::Box);
  expect_vector(fines.region.min, {-0.1, -0.1, 0.5});
  expect_vector(fines.region.max, {0.1, 0.1, 0.9});
  EXPECT_EQ(fines.count, 10000);
  EXPECT_DOUBLE_EQ(fines.volume_fraction, 0);
  EXPECT_FALSE(fines.random_orientation);
  expect_vector(fines.velocity, {0, 0, -1});
  EXPECT_EQ(fines.seed, 42u);
  EXPECT_DOUBLE_EQ(fines.rate, 5000);
  EXPECT_DOUBLE_EQ(fines.start, 0.1);
  EXPECT_DOUBLE_EQ(fines.interval, 0.02);
}

TEST_F(FullScene, DiscreteSourceInACylinder) {
  const auto& mix = scene.sources.at(1);
  EXPECT_EQ(mix.sizes.kind, kdem::SizeDistributionConfig::Kind::Discrete);
  EXPECT_EQ(mix.sizes.radii, (std::vector<double>{0.003, 0.005}));
  EXPECT_EQ(mix.sizes.mass_fractions, (std::vector<double>{0.25, 0.75}));
  EXPECT_EQ(mix.region.kind, kdem::RegionConfig::Kind::Cylinder);
  expect_vector(mix.region.base_center, {0, 0, 1});
  EXPECT_DOUBLE_EQ(mix.region.radius, 0.2);
  EXPECT_DOUBLE_EQ(mix.region.height, 0.3);
  EXPECT_EQ(mix.count, 0);
  EXPECT_DOUBLE_EQ(mix.volume_fraction, 0.3);
  EXPECT_TRUE(mix.random_orientation);
  EXPECT_EQ(mix.seed, 1u);
  EXPECT_DOUBLE_EQ(mix.rate, 0);
  EXPECT_DOUBLE_EQ(mix.interval, 0.01);
}

TEST_F(FullScene, GaussianSource) {
  const auto& bell = scene.sources.at(2).sizes;
  EXPECT_EQ(bell.kind, kdem::SizeDistributionConfig::Kind::Gaussian);
  EXPECT_DOUBLE_EQ(bell.mean_radius, 0.004);
  EXPECT_DOUBLE_EQ(bell.std_radius, 0.0005);
  EXPECT_DOUBLE_EQ(bell.min_radius, 0.003);
  EXPECT_DOUBLE_EQ(bell.max_radius, 0.005);
}

TEST_F(FullScene, PlaneAndBoxWalls) {
  ASSERT_EQ(scene.walls.size(), 4u);
  const auto& floor = scene.walls[0];
  EXPECT_EQ(floor.name, "floor");
  EXPECT_EQ(floor.material, "steel");
  EXPECT_EQ(floor.kind, kdem::WallConfig::Kind::Plane);
  expect_vector(floor.point, {0, 0, -0.5});
  expect_vector(floor.normal, {0, 0, 1});
  EXPECT_FALSE(floor.motion.moves());
  const auto& bin = scene.walls[1];
  EXPECT_EQ(bin.kind, kdem::WallConfig::Kind::Box);
  expect_vector(bin.min, {-1, -1, -1});
  expect_vector(bin.max, {1, 1, 2});
  EXPECT_EQ(bin.open_faces, (std::vector<std::string>{"zmax", "xmin"}));
}

TEST_F(FullScene, CylinderWallWithNormalisedAxesAndMotion) {
  const auto& drum = scene.walls.at(2);
  EXPECT_EQ(drum.kind, kdem::WallConfig::Kind::Cylinder);
  expect_vector(drum.base_center, {0, 0, 0});
  expect_vector(drum.axis_direction, {0.6, 0, 0.8});
  EXPECT_DOUBLE_EQ(drum.radius, 0.5);
  EXPECT_DOUBLE_EQ(drum.length, 0.25);
  expect_vector(drum.motion.velocity, {0.1, 0, 0});
  expect_vector(drum.motion.axis_point, {0, 0, 0.1});
  expect_vector(drum.motion.axis_direction, {0, 1, 0});
  EXPECT_DOUBLE_EQ(drum.motion.rpm, 30);
  EXPECT_DOUBLE_EQ(drum.motion.start, 0.2);
  EXPECT_DOUBLE_EQ(drum.active_from, 0);
  EXPECT_GT(drum.active_until, 1e100);
}

TEST_F(FullScene, MeshWallResolvedAgainstTheSceneFolder) {
  const auto& funnel = scene.walls.at(3);
  EXPECT_EQ(funnel.kind, kdem::WallConfig::Kind::Mesh);
  const fs::path expected =
      fs::absolute(folder.path() / "meshes" / "funnel.stl").lexically_normal();
  EXPECT_EQ(funnel.file, expected.string());
  EXPECT_TRUE(fs::path(funnel.file).is_absolute());
  EXPECT_DOUBLE_EQ(funnel.scale, 0.001);
  expect_vector(funnel.translate, {0, 0, 0.3});
  EXPECT_DOUBLE_EQ(funnel.active_from, 0.1);
  EXPECT_DOUBLE_EQ(funnel.active_until, 0.75);
}

TEST_F(FullScene, OutletsAndOutput) {
  ASSERT_EQ(scene.outlets.size(), 1u);
  EXPECT_EQ(scene.outlets[0].name, "exit");
  expect_vector(scene.outlets[0].min, {-0.05, -0.05, -1});
  expect_vector(scene.outlets[0].max, {0.05, 0.05, -0.9});
  EXPECT_EQ(scene.output.directory, "results/hopper");
  EXPECT_DOUBLE_EQ(scene.output.frame_interval, 0.01);
  EXPECT_DOUBLE_EQ(scene.output.series_interval, 0.001);
  EXPECT_DOUBLE_EQ(scene.output.checkpoint_interval, 0.5);
  EXPECT_FALSE(scene.output.final_checkpoint);
}

TEST(SceneDefaults, MinimalSceneGetsTheDocumentedDefaults) {
  const SceneConfig scene = load_text(minimal_scene());
  expect_vector(scene.gravity, {0, 0, -9.81});
  EXPECT_FALSE(scene.has_domain);
  EXPECT_TRUE(scene.interactions.empty());
  EXPECT_TRUE(scene.walls.empty());
  EXPECT_TRUE(scene.outlets.empty());
  EXPECT_EQ(scene.output.directory, "out");
  EXPECT_DOUBLE_EQ(scene.output.frame_interval, 0);
  EXPECT_TRUE(scene.output.final_checkpoint);
  EXPECT_EQ(scene.checks.interval, 10);
  EXPECT_DOUBLE_EQ(scene.checks.max_overlap_ratio, 0.25);
  EXPECT_DOUBLE_EQ(scene.checks.max_energy_gain, 1.0);
  EXPECT_EQ(scene.checks.leaving_domain, kdem::ChecksConfig::Leaving::Remove);
  EXPECT_EQ(scene.sources.at(0).sizes.kind, kdem::SizeDistributionConfig::Kind::Monodisperse);
  EXPECT_DOUBLE_EQ(scene.sources.at(0).sizes.radius, 0.002);
}

TEST(SceneDefaults, SkinIsADefaultFractionOfTheSmallestRadius) {
  const SceneConfig scene = load_text(minimal_scene_plus(R"(  - name: small
    material: glass
    size: {distribution: discrete, radii: [0.004, 0.0005], mass_fractions: [0.5, 0.5]}
    region: {box: {min: [0, 0, 0], max: [1, 1, 1]}}
    count: 3
)"));
  EXPECT_DOUBLE_EQ(scene.skin, 0.4 * 0.0005);
}

TEST(SceneFile, LoadsAFileAndResolvesMeshesAgainstItsFolder) {
  ScratchFolder folder;
  folder.write("cases/drop/wall.stl", "solid w\nendsolid w\n");
  const fs::path scene_file = folder.write(
      "cases/drop/drop.yaml", minimal_scene_plus("walls:\n  - name: w\n    material: glass\n"
                                                 "    mesh: {file: wall.stl}\n"));
  const SceneConfig scene = kdem::load_scene(scene_file.string());
  EXPECT_EQ(scene.source_file, scene_file.string());
  ASSERT_EQ(scene.walls.size(), 1u);
  EXPECT_EQ(scene.walls[0].file,
            fs::absolute(folder.path() / "cases/drop/wall.stl").lexically_normal().string());
}

// ---- the file itself ---------------------------------------------------------------------------

std::string load_file_error(const std::string& path) {
  try {
    kdem::load_scene(path);
  } catch (const SceneError& error) {
    return error.what();
  }
  return "(the scene was accepted)";
}

TEST(SceneFileErrors, MissingFile) {
  ScratchFolder folder;
  const std::string path = (folder.path() / "absent.yaml").string();
  EXPECT_EQ(load_file_error(path), path + ": cannot read the scene file (no such file)");
}

TEST(SceneFileErrors, FolderInsteadOfAFile) {
  ScratchFolder folder;
  const std::string path = folder.path().string();
  EXPECT_EQ(load_file_error(path), path + ": cannot read the scene file (it is a folder)");
}

TEST(SceneFileErrors, ErrorsNameTheFileAsGiven) {
  ScratchFolder folder;
  const fs::path scene_file = folder.write("bad.yaml", "time_step: -1\n");
  EXPECT_EQ(load_file_error(scene_file.string()),
            scene_file.string() +
                ":1:12: time_step: expected a positive number in seconds, got \"-1\"");
}

TEST(SceneSyntaxErrors, YamlSyntaxErrorHasItsPosition) {
  const std::string yaml = "time_step: 1e-5\nduration: [1, 2\nmaterials: []\n";
  std::string message;
  try {
    load_text(yaml);
  } catch (const SceneError& error) {
    message = error.what();
    EXPECT_GE(error.line(), 2);
  }
  EXPECT_EQ(message.rfind("scene.yaml:", 0), 0u) << message;
  EXPECT_NE(message.find("YAML syntax error: "), std::string::npos) << message;
}

TEST(SceneSyntaxErrors, BadIndentation) {
  const std::string yaml = "time_step: 1e-5\n  duration: 1\n";
  std::string message;
  try {
    load_text(yaml);
  } catch (const SceneError& error) {
    message = error.what();
  }
  EXPECT_NE(message.find("scene.yaml:2:"), std::string::npos) << message;
  EXPECT_NE(message.find("YAML syntax error"), std::string::npos) << message;
}

TEST(SceneSyntaxErrors, EmptyFile) {
  std::string message;
  try {
    load_text("# nothing here\n");
  } catch (const SceneError& error) {
    message = error.what();
  }
  EXPECT_EQ(message.rfind("scene.yaml:1:1: expected a mapping with keys time_step", 0), 0u)
      << message;
}

TEST(SceneSyntaxErrors, TwoDocuments) {
  std::string message;
  try {
    load_text(minimal_scene() + "---\nduration: 1\n");
  } catch (const SceneError& error) {
    message = error.what();
  }
  EXPECT_EQ(message.rfind("scene.yaml:15:", 0), 0u) << message;
  EXPECT_NE(message.find("expected a single YAML document, got 2"), std::string::npos) << message;
}

// yaml-cpp 0.7's LoadAll loops for ever (memory growing) on a lone comma; the loader reads the
// documents itself and refuses the text.
TEST(SceneSyntaxErrors, LoneCommaIsRefusedNotLoopedOn) {
  std::string message;
  try {
    load_text(",");
  } catch (const SceneError& error) {
    message = error.what();
  }
  EXPECT_EQ(message.rfind("scene.yaml:", 0), 0u) << message;
  EXPECT_NE(message.find("expected a mapping"), std::string::npos) << message;
}

TEST(SceneSyntaxErrors, TopLevelMustBeAMapping) {
  std::string message;
  try {
    load_text("- 1\n- 2\n");
  } catch (const SceneError& error) {
    message = error.what();
  }
  EXPECT_EQ(message.rfind("scene.yaml:1:1: expected a mapping with keys time_step", 0), 0u)
      << message;
  EXPECT_NE(message.find("got [1, 2]"), std::string::npos) << message;
}

// ---- keys ---------------------------------------------------------------------------------------

TEST(SceneKeyErrors, UnknownTopLevelKeyListsTheAllowedKeysAndSuggestsOne) {
  EXPECT_TRUE(fails_with(
      minimal_scene_plus("durration: 1\n"), 14, "durration",
      "expected one of the keys time_step, duration, gravity, skin, sort_by_cell, domain, "
      "materials, interactions, shapes, superquadric_contact, poly_superquadric_contact, "
      "clump_contact, dilated_polyhedron_contact, level_set_contact, "
      "particles, walls, outlets, output, checks, got the key "
      "\"durration\" (did you mean \"duration\"?)"));
}

TEST(SceneChecks, EveryKeyIsRead) {
  const SceneConfig scene = load_text(minimal_scene_plus(
      "checks: {interval: 5, max_overlap_ratio: 0.1, max_energy_gain: 3, leaving_domain: stop}\n"));
  EXPECT_EQ(scene.checks.interval, 5);
  EXPECT_DOUBLE_EQ(scene.checks.max_overlap_ratio, 0.1);
  EXPECT_DOUBLE_EQ(scene.checks.max_energy_gain, 3);
  EXPECT_EQ(scene.checks.leaving_domain, kdem::ChecksConfig::Leaving::Stop);
}

TEST(SceneChecks, BadValuesAreRefusedByKey) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("checks: {interval: 0}\n"), 14, "checks.interval",
                         "expected a whole number >= 1"));
  EXPECT_TRUE(fails_with(minimal_scene_plus("checks: {max_overlap_ratio: -1}\n"), 14,
                         "checks.max_overlap_ratio", "expected a positive number"));
  EXPECT_TRUE(fails_with(minimal_scene_plus("checks: {max_energy_gain: .nan}\n"), 14,
                         "checks.max_energy_gain", "expected a positive number"));
  EXPECT_TRUE(fails_with(minimal_scene_plus("checks: {leaving_domain: ignore}\n"), 14,
                         "checks.leaving_domain", "expected one of remove, stop"));
  EXPECT_TRUE(fails_with(minimal_scene_plus("checks: {intervall: 3}\n"), 14, "checks.intervall",
                         "expected one of the keys interval, max_overlap_ratio"));
}

TEST(SceneKeyErrors, UnknownNestedKey) {
  EXPECT_TRUE(fails_with(minimal_scene_with(6, "    young: 1.0e7"), 6, "materials[0].young",
                         "expected one of the keys name, density, youngs_modulus, poisson_ratio, "
                         "restitution, friction, rolling_friction, got the key \"young\""));
}

TEST(SceneKeyErrors, KeyOfAnotherSizeDistribution) {
  EXPECT_TRUE(fails_with(minimal_scene_with(11, "    size: {radius: 0.002, min_radius: 0.001}"), 11,
                         "particles[0].size.min_radius",
                         "expected one of the keys distribution, radius (for distribution "
                         "monodisperse), got the key \"min_radius\""));
}

TEST(SceneKeyErrors, DuplicateKey) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("time_step: 2.0e-5\n"), 14, "time_step",
                         "expected each key once, got \"time_step\" again (first at line 1)"));
}

TEST(SceneKeyErrors, MissingTopLevelKey) {
  EXPECT_TRUE(fails_with(minimal_scene_with(2, "skin: 0.001"), 1, "duration",
                         "expected a positive number in seconds, got nothing (required key is "
                         "missing)"));
}

TEST(SceneKeyErrors, MissingMaterialKey) {
  EXPECT_TRUE(fails_with(minimal_scene_with(5, "    friction: 0.3"), 4, "materials[0].density",
                         "expected a positive number in kg/m^3, got nothing (required key is "
                         "missing)"));
}

TEST(SceneKeyErrors, MissingSourceSize) {
  EXPECT_TRUE(fails_with(minimal_scene_with(11, "    seed: 3"), 9, "particles[0]",
                         "expected exactly one of the keys size, shape, got none"));
}

TEST(SceneKeyErrors, MissingMaterialsList) {
  std::vector<std::string> lines(minimal_lines.begin(), minimal_lines.begin() + 2);
  lines.insert(lines.end(), minimal_lines.begin() + 7, minimal_lines.end());
  EXPECT_TRUE(fails_with(join_lines(lines), 1, "materials",
                         "expected a non-empty sequence of materials, got nothing"));
}

TEST(SceneKeyErrors, EmptyValue) {
  EXPECT_TRUE(fails_with(minimal_scene_with(5, "    density:"), 5, "materials[0].density",
                         "expected a positive number in kg/m^3, got an empty value"));
}

TEST(SceneKeyErrors, WallWithoutAShape) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("walls:\n  - name: w\n    material: glass\n"), 15,
                         "walls[0]",
                         "expected exactly one of the keys plane, box, cylinder, mesh, got none"));
}

TEST(SceneKeyErrors, WallWithTwoShapes) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("walls:\n  - name: w\n    material: glass\n"
                                            "    plane: {point: [0, 0, 0], normal: [0, 0, 1]}\n"
                                            "    box: {min: [0, 0, 0], max: [1, 1, 1]}\n"),
                         18, "walls[0]",
                         "expected exactly one of the keys plane, box, cylinder, mesh, got plane "
                         "and box"));
}

TEST(SceneKeyErrors, RegionWithoutAShape) {
  EXPECT_TRUE(fails_with(minimal_scene_with(12, "    region: {}"), 12, "particles[0].region",
                         "expected exactly one of the keys box, cylinder, got none"));
}

TEST(SceneKeyErrors, SourceWithBothCountAndVolumeFraction) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("    volume_fraction: 0.3\n"), 14, "particles[0]",
                         "expected exactly one of the keys count, volume_fraction, got count and "
                         "volume_fraction"));
}

TEST(SceneKeyErrors, SourceWithNeitherCountNorVolumeFraction) {
  EXPECT_TRUE(fails_with(minimal_scene_with(13, "    seed: 7"), 9, "particles[0]",
                         "expected exactly one of the keys count, volume_fraction, got none"));
}

// ---- types -------------------------------------------------------------------------------------

TEST(SceneTypeErrors, TextForANumber) {
  EXPECT_TRUE(fails_with(minimal_scene_with(1, "time_step: fast"), 1, "time_step",
                         "expected a positive number in seconds, got \"fast\""));
}

TEST(SceneTypeErrors, SequenceForANumber) {
  EXPECT_TRUE(fails_with(minimal_scene_with(7, "    poisson_ratio: [0.3]"), 7,
                         "materials[0].poisson_ratio",
                         "expected a Poisson ratio in (-1, 0.5), got [0.3]"));
}

TEST(SceneTypeErrors, NumberForAVector) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("gravity: -9.81\n"), 14, "gravity",
                         "expected a sequence of 3 numbers [x, y, z] in m/s^2, got \"-9.81\""));
}

TEST(SceneTypeErrors, VectorOfTwo) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("gravity: [0, -9.81]\n"), 14, "gravity",
                         "expected a sequence of 3 numbers [x, y, z] in m/s^2, got [0, -9.81]"));
}

TEST(SceneTypeErrors, VectorItemNotANumber) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("gravity: [0, 0, down]\n"), 14, "gravity[2]",
                         "expected a number in m/s^2, got \"down\""));
}

TEST(SceneTypeErrors, NotABoolean) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("    random_orientation: maybe\n"), 14,
                         "particles[0].random_orientation",
                         "expected true or false, got \"maybe\""));
}

TEST(SceneTypeErrors, MappingForAList) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("walls: {name: floor}\n"), 14, "walls",
                         "expected a sequence of walls, got a mapping"));
}

TEST(SceneTypeErrors, ListForAMapping) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("output: [out]\n"), 14, "output",
                         "expected a mapping with keys directory, frame_interval"));
}

TEST(SceneTypeErrors, FractionalCount) {
  EXPECT_TRUE(fails_with(minimal_scene_with(13, "    count: 2.5"), 13, "particles[0].count",
                         "expected a whole number >= 1, got \"2.5\""));
}

TEST(SceneTypeErrors, UnknownDistribution) {
  EXPECT_TRUE(fails_with(minimal_scene_with(11, "    size: {distribution: lognormal, radius: 1}"),
                         11, "particles[0].size.distribution",
                         "expected one of monodisperse, uniform, gaussian, discrete, got "
                         "\"lognormal\""));
}

TEST(SceneTypeErrors, UnknownBoxFace) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("walls:\n  - name: w\n    material: glass\n"
                                            "    box: {min: [0, 0, 0], max: [1, 1, 1], "
                                            "open_faces: [top]}\n"),
                         17, "walls[0].box.open_faces[0]",
                         "expected one of xmin, xmax, ymin, ymax, zmin, zmax, got \"top\""));
}

// ---- ranges ------------------------------------------------------------------------------------

// Line `line` of the minimal scene replaced by `replacement`: refused at `reported_line`.
struct RangeCase {
  int line;
  std::string replacement;
  int reported_line;
  std::string key_path;
  std::string expectation;
};

void PrintTo(const RangeCase& bad, std::ostream* out) {
  *out << bad.key_path;
}

class SceneRangeErrors : public testing::TestWithParam<RangeCase> {};

TEST_P(SceneRangeErrors, ValueOutsideItsRange) {
  const RangeCase& bad = GetParam();
  EXPECT_TRUE(fails_with(minimal_scene_with(bad.line, bad.replacement), bad.reported_line,
                         bad.key_path, bad.expectation));
}

INSTANTIATE_TEST_SUITE_P(
    Values, SceneRangeErrors,
    testing::Values(
        RangeCase{1, "time_step: 0", 1, "time_step",
                  "expected a positive number in seconds, got \"0\""},
        RangeCase{1, "time_step: .nan", 1, "time_step", "expected a positive number in seconds"},
        RangeCase{2, "duration: -1", 2, "duration",
                  "expected a positive number in seconds, got \"-1\""},
        RangeCase{5, "    density: -2500", 5, "materials[0].density",
                  "expected a positive number in kg/m^3, got \"-2500\""},
        RangeCase{6, "    youngs_modulus: 0", 6, "materials[0].youngs_modulus",
                  "expected a positive number in Pa, got \"0\""},
        RangeCase{7, "    poisson_ratio: 0.5", 7, "materials[0].poisson_ratio",
                  "expected a Poisson ratio in (-1, 0.5), got \"0.5\""},
        RangeCase{7, "    poisson_ratio: -1", 7, "materials[0].poisson_ratio",
                  "expected a Poisson ratio in (-1, 0.5), got \"-1\""},
        RangeCase{7, "    poisson_ratio: 0.25\n    restitution: 0", 8, "materials[0].restitution",
                  "expected a coefficient of restitution in (0, 1], got \"0\""},
        RangeCase{7, "    poisson_ratio: 0.25\n    restitution: 1.2", 8, "materials[0].restitution",
                  "expected a coefficient of restitution in (0, 1], got \"1.2\""},
        RangeCase{7, "    poisson_ratio: 0.25\n    friction: -0.1", 8, "materials[0].friction",
                  "expected a friction coefficient >= 0, got \"-0.1\""},
        RangeCase{7, "    poisson_ratio: 0.25\n    rolling_friction: -0.1", 8,
                  "materials[0].rolling_friction",
                  "expected a friction coefficient >= 0, got \"-0.1\""},
        RangeCase{11, "    size: {radius: -0.01}", 11, "particles[0].size.radius",
                  "expected a positive number in metres, got \"-0.01\""},
        RangeCase{11, "    size: {distribution: uniform, min_radius: 0.003, max_radius: 0.002}", 11,
                  "particles[0].size.max_radius",
                  "expected a radius >= min_radius (0.003 m), got \"0.002\""},
        RangeCase{11,
                  "    size: {distribution: gaussian, mean_radius: 0.01, std_radius: 0.001, "
                  "min_radius: 0.001, max_radius: 0.002}",
                  11, "particles[0].size.mean_radius",
                  "expected a radius between min_radius (0.001 m) and max_radius (0.002 m), got "
                  "\"0.01\""},
        RangeCase{
            11,
            "    size: {distribution: discrete, radii: [0.001, 0.002], mass_fractions: [0.5, 0.4]}",
            11, "particles[0].size.mass_fractions",
            "expected mass fractions summing to 1 (within 1e-6), got [0.5, 0.4] (they sum "
            "to 0.9)"},
        RangeCase{11,
                  "    size: {distribution: discrete, radii: [0.001, 0.002], mass_fractions: [1]}",
                  11, "particles[0].size.mass_fractions",
                  "expected a sequence of 2 mass fractions, one per radius, got [1]"},
        RangeCase{
            11, "    size: {distribution: discrete, radii: [0.001, 0], mass_fractions: [1, 0]}", 11,
            "particles[0].size.radii[1]", "expected a positive number in metres, got \"0\""},
        RangeCase{12, "    region: {box: {min: [0, 0, 0], max: [0.1, 0.1, -0.1]}}", 12,
                  "particles[0].region.box.max",
                  "expected a corner greater than min = [0, 0, 0] in x, y and z (in metres), got "
                  "[0.1, 0.1, -0.1]"},
        RangeCase{12, "    region: {cylinder: {base_center: [0, 0, 0], radius: 0.1, height: 0}}",
                  12, "particles[0].region.cylinder.height",
                  "expected a positive number in metres, got \"0\""},
        RangeCase{13, "    count: 0", 13, "particles[0].count",
                  "expected a whole number >= 1, got \"0\""},
        RangeCase{13, "    volume_fraction: 0.8", 13, "particles[0].volume_fraction",
                  "expected a solid volume fraction in (0, 0.74], got \"0.8\""},
        RangeCase{13, "    count: 5\n    seed: -3", 14, "particles[0].seed",
                  "expected a whole number >= 0, got \"-3\""}));

TEST(SceneRangeErrors, InsertionOverTimeNeedsACount) {
  EXPECT_TRUE(fails_with(minimal_scene_with(13, "    volume_fraction: 0.3\n    rate: 100"), 14,
                         "particles[0].rate",
                         "expected 0 for a source with a volume_fraction, got \"100\" (insertion "
                         "over time needs a count)"));
}

TEST(SceneRangeErrors, SkinMustBePositive) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("skin: 0\n"), 14, "skin",
                         "expected a positive number in metres, got \"0\""));
}

TEST(SceneRangeErrors, WallRadius) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("walls:\n  - name: drum\n    material: glass\n"
                                            "    cylinder: {base_center: [0, 0, 0], radius: "
                                            "-0.01, length: 1}\n"),
                         17, "walls[0].cylinder.radius",
                         "expected a positive number in metres, got \"-0.01\""));
}

TEST(SceneRangeErrors, ZeroLengthNormal) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("walls:\n  - name: floor\n    material: glass\n"
                                            "    plane: {point: [0, 0, 0], normal: [0, 0, 0]}\n"),
                         17, "walls[0].plane.normal",
                         "expected a direction vector of non-zero length, got [0, 0, 0]"));
}

TEST(SceneRangeErrors, ActiveUntilBeforeActiveFrom) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("walls:\n  - name: gate\n    material: glass\n"
                                            "    plane: {point: [0, 0, 0], normal: [0, 0, 1]}\n"
                                            "    active_from: 0.2\n    active_until: 0.1\n"),
                         19, "walls[0].active_until",
                         "expected a time after active_from (0.2 s), got \"0.1\""));
}

TEST(SceneRangeErrors, DomainCornersInWrongOrder) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("domain:\n  min: [0, 0, 0]\n  max: [1, 0, 1]\n"), 16,
                         "domain.max", "expected a corner greater than min = [0, 0, 0]"));
}

TEST(SceneRangeErrors, RegionOutsideTheDomain) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("domain: {min: [0, 0, 0], max: [0.05, 1, 1]}\n"), 12,
                         "particles[0].region",
                         "expected a region inside the domain [0, 0, 0] .. [0.05, 1, 1], got one "
                         "reaching [0, 0, 0] .. [0.1, 0.1, 0.1]"));
}

// ---- references and names ----------------------------------------------------------------------

TEST(SceneReferenceErrors, SourceWithUndefinedMaterial) {
  EXPECT_TRUE(fails_with(minimal_scene_with(10, "    material: glas"), 10, "particles[0].material",
                         "expected the name of a material defined under materials (glass), got "
                         "\"glas\""));
}

TEST(SceneReferenceErrors, WallWithUndefinedMaterial) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("walls:\n  - name: floor\n    material: steel\n"
                                            "    plane: {point: [0, 0, 0], normal: [0, 0, 1]}\n"),
                         16, "walls[0].material",
                         "expected the name of a material defined under materials (glass), got "
                         "\"steel\""));
}

TEST(SceneReferenceErrors, InteractionWithUndefinedMaterial) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("interactions:\n  - materials: [glass, rubber]\n"), 15,
                         "interactions[0].materials[1]",
                         "expected the name of a material defined under materials (glass), got "
                         "\"rubber\""));
}

TEST(SceneReferenceErrors, DuplicateMaterialName) {
  EXPECT_TRUE(fails_with(minimal_scene_with(8, "  - {name: glass, density: 1, youngs_modulus: 1, "
                                               "poisson_ratio: 0}\nparticles:"),
                         8, "materials[1].name",
                         "expected a name not used by another entry of materials, got \"glass\" "
                         "(already the name of materials[0].name at line 4)"));
}

TEST(SceneReferenceErrors, DuplicateSourceName) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("  - name: beads\n    material: glass\n"), 14,
                         "particles[1].name",
                         "expected a name not used by another entry of particles, got \"beads\""));
}

TEST(SceneReferenceErrors, DuplicateWallName) {
  EXPECT_TRUE(fails_with(
      minimal_scene_plus(
          "walls:\n"
          "  - {name: w, material: glass, plane: {point: [0, 0, 0], normal: [0, 0, 1]}}\n"
          "  - {name: w, material: glass, plane: {point: [0, 0, 0], normal: [0, 0, 1]}}\n"),
      16, "walls[1].name", "expected a name not used by another entry of walls, got \"w\""));
}

TEST(SceneReferenceErrors, DuplicateOutletName) {
  EXPECT_TRUE(fails_with(
      minimal_scene_plus("outlets:\n"
                         "  - {name: out, box: {min: [0, 0, 0], max: [1, 1, 1]}}\n"
                         "  - {name: out, box: {min: [0, 0, 0], max: [1, 1, 1]}}\n"),
      16, "outlets[1].name", "expected a name not used by another entry of outlets, got \"out\""));
}

TEST(SceneReferenceErrors, DuplicateInteractionPair) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("interactions:\n  - materials: [glass, glass]\n"
                                            "  - materials: [glass, glass]\n    friction: 1\n"),
                         16, "interactions[1].materials",
                         "expected a name not used by another entry of interactions"));
}

TEST(SceneReferenceErrors, MissingMeshFile) {
  ScratchFolder folder;
  const std::string expected_place =
      fs::absolute(folder.path() / "parts" / "funnel.stl").lexically_normal().string();
  EXPECT_TRUE(
      fails_with(minimal_scene_plus("walls:\n  - name: funnel\n    material: glass\n"
                                    "    mesh: {file: parts/funnel.stl}\n"),
                 17, "walls[0].mesh.file",
                 "expected the path of an existing STL or OBJ file (relative to the scene file's "
                 "folder), got \"parts/funnel.stl\" (no file at " +
                     expected_place + ")",
                 folder.path().string()));
}

TEST(SceneReferenceErrors, MeshFileOfAnotherFormat) {
  ScratchFolder folder;
  folder.write("parts/funnel.ply", "ply\n");
  EXPECT_TRUE(fails_with(minimal_scene_plus("walls:\n  - name: funnel\n    material: glass\n"
                                            "    mesh: {file: parts/funnel.ply}\n"),
                         17, "walls[0].mesh.file", "(the name ends in neither .stl nor .obj)",
                         folder.path().string()));
}

TEST(SceneErrorFields, CarryLineColumnAndKeyPath) {
  try {
    load_text(minimal_scene_with(5, "    density: -1"));
    FAIL() << "the scene was accepted";
  } catch (const SceneError& error) {
    EXPECT_EQ(error.line(), 5);
    EXPECT_EQ(error.column(), 14);
    EXPECT_EQ(error.key_path(), "materials[0].density");
  }
}

// ---- superquadric shapes ----------------------------------------------------------------------

const std::string cube_shape = "shapes:\n"                                // 14
                               "  - name: cube\n"                         // 15
                               "    superquadric:\n"                      // 16
                               "      half_axes: [0.001, 0.002, 0.003]\n" // 17
                               "      blockiness: [8, 6]\n";              // 18

TEST(SceneShapes, ShapedSourceTakesTheTemplate) {
  const SceneConfig scene =
      load_text(minimal_scene_with(11, "    shape: cube") + cube_shape +
                "superquadric_contact: {tolerance: 1.0e-8, max_iterations: 25, "
                "curvature_limit: 3}\n");
  ASSERT_EQ(scene.shapes.size(), 1u);
  EXPECT_EQ(scene.shapes[0].name, "cube");
  EXPECT_EQ(scene.shapes[0].family, "superquadric");
  const kdem::SuperquadricShapeParameters& cube = kdem::superquadric_parameters(scene.shapes[0]);
  EXPECT_EQ(cube.half_axes, (kdem::Vec3d{0.001, 0.002, 0.003}));
  EXPECT_EQ(cube.n1, 8);
  EXPECT_EQ(cube.n2, 6);
  EXPECT_EQ(scene.sources[0].shape, "cube");
  // The default skin follows the smallest semi-axis of a shaped source.
  EXPECT_DOUBLE_EQ(scene.skin, kdem::default_skin_per_radius * 0.001);
  EXPECT_EQ(kdem::superquadric_contact(scene).tolerance, 1e-8);
  EXPECT_EQ(kdem::superquadric_contact(scene).max_iterations, 25);
  EXPECT_EQ(kdem::superquadric_contact(scene).curvature_limit, 3);
}

TEST(SceneShapes, SpheresHaveNoShape) {
  const SceneConfig scene = load_text(minimal_scene());
  EXPECT_TRUE(scene.shapes.empty());
  EXPECT_TRUE(scene.sources[0].shape.empty());
  EXPECT_EQ(kdem::superquadric_contact(scene).curvature_limit, 2);
}

TEST(SceneShapes, AShapeNamesExactlyOneFamily) {
  const std::string none = "shapes:\n  - name: cube\n    tag: x\n";
  EXPECT_TRUE(fails_with(minimal_scene_plus(none), 16, "shapes[0].tag",
                         "expected one of the keys name, superquadric, poly_superquadric, clump, "
                         "dilated_polyhedron, level_set, got the key \"tag\""));
  std::string missing = "shapes:\n  - name: cube\n";
  EXPECT_TRUE(fails_with(minimal_scene_plus(missing), 15, "shapes[0]",
                         "expected exactly one of the keys superquadric, poly_superquadric, clump, "
                         "dilated_polyhedron, level_set, got none"));
}

TEST(SceneShapes, UnknownShapeNamesTheDefinedOnes) {
  EXPECT_TRUE(fails_with(minimal_scene_with(11, "    shape: sphere") + cube_shape, 11,
                         "particles[0].shape",
                         "expected the name of a shape defined under shapes (cube)"));
}

TEST(SceneShapes, ShapeWithoutShapesList) {
  EXPECT_TRUE(fails_with(minimal_scene_with(11, "    shape: cube"), 11, "particles[0].shape",
                         "(none is defined)"));
}

TEST(SceneShapes, SizeAndShapeTogether) {
  EXPECT_TRUE(fails_with(minimal_scene_with(13, "    shape: cube") + cube_shape, 13, "particles[0]",
                         "expected exactly one of the keys size, shape, got size and "
                         "shape"));
}

TEST(SceneShapes, BlockinessOutOfRange) {
  std::string text = cube_shape;
  text.replace(text.find("[8, 6]"), 6, "[8, 1.5]");
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 18, "shapes[0].superquadric.blockiness[1]",
                         "expected a blockiness exponent in [2, 20], got \"1.5\""));
}

TEST(SceneShapes, BlockinessNeedsTwoExponents) {
  std::string text = cube_shape;
  text.replace(text.find("[8, 6]"), 6, "[8]");
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 18, "shapes[0].superquadric.blockiness",
                         "expected a sequence [n1, n2] of two blockiness exponents"));
}

TEST(SceneShapes, NonPositiveSemiAxis) {
  std::string text = cube_shape;
  text.replace(text.find("0.002"), 5, "0");
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 17, "shapes[0].superquadric.half_axes",
                         "expected three positive semi-axes a, b, c in metres"));
}

TEST(SceneShapes, DuplicateShapeName) {
  EXPECT_TRUE(fails_with(minimal_scene_plus(cube_shape + "  - name: cube\n    superquadric: "
                                                         "{half_axes: [1, 1, 1], blockiness: [2, "
                                                         "2]}\n"),
                         19, "shapes[1].name", "a name not used by another entry of shapes"));
}

TEST(SceneShapes, ToleranceOutOfRange) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("superquadric_contact: {tolerance: 0.5}\n"), 14,
                         "superquadric_contact.tolerance",
                         "expected a Newton tolerance in (0, 1e-2], got \"0.5\""));
}

// ---- poly-superquadric shapes -----------------------------------------------------------------

const std::string hemisphere_shape = "shapes:\n"                                       // 14
                                     "  - name: hemisphere\n"                          // 15
                                     "    poly_superquadric:\n"                        // 16
                                     "      half_axes_plus: [0.006, 0.006, 0.006]\n"   // 17
                                     "      half_axes_minus: [1.0e-5, 0.006, 0.005]\n" // 18
                                     "      blockiness: [2, 3]\n";                     // 19

TEST(ScenePolySuperquadrics, ShapeAndSettingsAreRead) {
  const SceneConfig scene =
      load_text(minimal_scene_with(11, "    shape: hemisphere") + hemisphere_shape +
                "poly_superquadric_contact: {tolerance: 1.0e-9, curvature_limit: 4, "
                "separation_certificates: false}\n");
  ASSERT_EQ(scene.shapes.size(), 1u);
  EXPECT_EQ(scene.shapes[0].family, "poly_superquadric");
  const kdem::PolySuperquadricShapeParameters& shape =
      kdem::poly_superquadric_parameters(scene.shapes[0]);
  EXPECT_EQ(shape.half_axes_plus, (kdem::Vec3d{0.006, 0.006, 0.006}));
  EXPECT_EQ(shape.half_axes_minus, (kdem::Vec3d{1e-5, 0.006, 0.005}));
  EXPECT_EQ(shape.n1, 2);
  EXPECT_EQ(shape.n2, 3);
  // The default skin follows the smallest half-width (r+ + r-) / 2, not the thin cap's extent.
  EXPECT_DOUBLE_EQ(scene.skin, kdem::default_skin_per_radius * 0.5 * (0.006 + 1e-5));
  const auto& settings = dynamic_cast<const kdem::SuperquadricContactConfig&>(
      *scene.family_settings.at("poly_superquadric"));
  EXPECT_EQ(settings.tolerance, 1e-9);
  EXPECT_EQ(settings.curvature_limit, 4);
  EXPECT_FALSE(settings.separation_certificates);
  EXPECT_THROW(kdem::superquadric_parameters(scene.shapes[0]), std::logic_error);
}

TEST(ScenePolySuperquadrics, NonPositiveExtentNamesItsSide) {
  std::string text = hemisphere_shape;
  text.replace(text.find("1.0e-5"), 6, "0");
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 18,
                         "shapes[0].poly_superquadric.half_axes_minus",
                         "expected three positive extents r_x-, r_y-, r_z- in metres"));
  text = hemisphere_shape;
  text.replace(text.find("[0.006, 0.006, 0.006]"), 21, "[0.006, 0.006]");
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 17, "shapes[0].poly_superquadric.half_axes_plus",
                         "r_x+, r_y+, r_z+"));
}

TEST(ScenePolySuperquadrics, MissingKeyAndBlockinessOutOfRange) {
  std::string text = hemisphere_shape;
  text.erase(text.find("      half_axes_minus"),
             std::string("      half_axes_minus: [1.0e-5, 0.006, 0.005]\n").size());
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 17,
                         "shapes[0].poly_superquadric.half_axes_minus",
                         "got nothing (required key is missing)"));
  text = hemisphere_shape;
  text.replace(text.find("[2, 3]"), 6, "[2, 30]");
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 19, "shapes[0].poly_superquadric.blockiness[1]",
                         "expected a blockiness exponent in [2, 20], got \"30\""));
}

TEST(ScenePolySuperquadrics, SettingsRefuseTheSuperquadricsOwnKeys) {
  // Lanes and start extrapolation belong to the superquadric narrow phase alone.
  EXPECT_TRUE(fails_with(minimal_scene_plus("poly_superquadric_contact: {lanes: false}\n"), 14,
                         "poly_superquadric_contact.lanes", "got the key \"lanes\""));
}

// ---- clump shapes ------------------------------------------------------------------------------

const std::string rod_shape = "shapes:\n"         // 14
                              "  - name: rod\n"   // 15
                              "    clump:\n"      // 16
                              "      elements:\n" // 17
                              "        - superquadric: {half_axes: [0.006, 0.006, 0.006], "
                              "blockiness: [10, 2]}\n"                // 18
                              "          position: [0, 0, 0]\n"       // 19
                              "          orientation: [2, 0, 0, 0]\n" // 20
                              "        - sphere: {radius: 0.006}\n"   // 21
                              "          position: [0, 0, 0.006]\n"   // 22
                              "      equivalent_diameter: 0.005\n";   // 23

TEST(SceneClumps, ShapeAndSettingsAreRead) {
  const SceneConfig scene =
      load_text(minimal_scene_with(11, "    shape: rod") + rod_shape +
                "clump_contact: {tolerance: 1.0e-9, seam: summed, seam_distance: 0.25, "
                "seam_angle: 20}\n");
  ASSERT_EQ(scene.shapes.size(), 1u);
  EXPECT_EQ(scene.shapes[0].family, "clump");
  const kdem::ClumpShapeParameters& clump = kdem::clump_parameters(scene.shapes[0]);
  ASSERT_EQ(clump.elements.size(), 2u);
  EXPECT_FALSE(clump.elements[0].sphere);
  EXPECT_EQ(clump.elements[0].n1, 10);
  EXPECT_EQ(clump.elements[0].orientation, (std::array<double, 4>{1, 0, 0, 0})); // normalised
  EXPECT_TRUE(clump.elements[1].sphere);
  EXPECT_EQ(clump.elements[1].half_axes, (kdem::Vec3d{0.006, 0.006, 0.006}));
  EXPECT_EQ(clump.elements[1].position, (kdem::Vec3d{0, 0, 0.006}));
  EXPECT_EQ(clump.equivalent_diameter, 0.005);
  EXPECT_EQ(clump.union_precision, 1e-4);
  const auto& settings =
      dynamic_cast<const kdem::ClumpContactConfig&>(*scene.family_settings.at("clump"));
  EXPECT_EQ(settings.tolerance, 1e-9);
  EXPECT_FALSE(settings.seam_weighted);
  EXPECT_EQ(settings.seam_distance, 0.25);
  EXPECT_EQ(settings.seam_angle, 20);
}

TEST(SceneClumps, ElementErrorsNameTheElement) {
  std::string text = rod_shape;
  text.replace(text.find("sphere: {radius: 0.006}"), 23, "sphere: {radius: 0}");
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 21, "shapes[0].clump.elements[1].sphere.radius",
                         "expected a positive number in m, got \"0\""));
  text = rod_shape;
  text.replace(text.find("          position: [0, 0, 0.006]\n"), 34,
               "          position: [0, 0, 0.006]\n          orientation: [1, 0, 0, 0]\n");
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 23, "shapes[0].clump.elements[1].orientation",
                         "expected no orientation for a sphere element"));
  text = rod_shape;
  text.replace(text.find("[2, 0, 0, 0]"), 12, "[0, 0, 0, 0]");
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 20, "shapes[0].clump.elements[0].orientation",
                         "expected a quaternion [w, x, y, z] of non-zero length"));
  text = rod_shape;
  text.replace(text.find("        - sphere: {radius: 0.006}"), 33,
               "        - sphere: {radius: 0.006}\n          superquadric: {half_axes: [1, 1, 1], "
               "blockiness: [2, 2]}");
  EXPECT_TRUE(fails_with(minimal_scene_plus(text), 22, "shapes[0].clump.elements[1]",
                         "expected exactly one of the keys sphere, superquadric, got sphere and "
                         "superquadric"));
}

TEST(SceneClumps, ElementListMustHoldOneToSixteen) {
  const std::string empty = "shapes:\n  - name: rod\n    clump: {elements: []}\n";
  EXPECT_TRUE(fails_with(minimal_scene_plus(empty), 16, "shapes[0].clump.elements",
                         "expected a sequence of 1 to 16 elements"));
  std::string many = "shapes:\n  - name: rod\n    clump:\n      elements:\n";
  for (int k = 0; k < 17; ++k)
    many += "        - {sphere: {radius: 0.001}, position: [" + std::to_string(0.001 * k) +
            ", 0, 0]}\n";
  EXPECT_TRUE(fails_with(minimal_scene_plus(many), 18, "shapes[0].clump.elements",
                         "expected a sequence of 1 to 16 elements"));
}

TEST(SceneClumps, SeamSettingsAreChecked) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("clump_contact: {seam: doubled}\n"), 14,
                         "clump_contact.seam", "doubled"));
  EXPECT_TRUE(fails_with(minimal_scene_plus("clump_contact: {seam_angle: 90}\n"), 14,
                         "clump_contact.seam_angle", "expected an angle in degrees in (0, 90)"));
  EXPECT_TRUE(fails_with(minimal_scene_plus("clump_contact: {lanes: false}\n"), 14,
                         "clump_contact.lanes", "got the key \"lanes\""));
}

TEST(SceneDilatedPolyhedra, ContactSettingsAreReadAndChecked) {
  const SceneConfig scene = load_text(minimal_scene_plus(
      "dilated_polyhedron_contact: {cone_slack: 1.0e-5, cone_fade: 0.05, merge_distance: 0.25, "
      "averaging: summed, averaging_angle: 20}\n"));
  const auto& settings = dynamic_cast<const kdem::DilatedPolyhedronContactConfig&>(
      *scene.family_settings.at("dilated_polyhedron"));
  EXPECT_EQ(settings.cone_slack, 1e-5);
  EXPECT_EQ(settings.cone_fade, 0.05);
  EXPECT_EQ(settings.merge_distance, 0.25);
  EXPECT_FALSE(settings.averaging);
  EXPECT_EQ(settings.averaging_angle, 20);
  const kdem::DilatedPolyhedronContactConfig defaults;
  EXPECT_EQ(defaults.cone_fade, 0.002);
  EXPECT_EQ(defaults.merge_distance, 0.5);
  EXPECT_TRUE(fails_with(minimal_scene_plus("dilated_polyhedron_contact: {cone_fade: 0.3}\n"), 14,
                         "dilated_polyhedron_contact.cone_fade",
                         "expected an angle in radians in [0, 0.2]"));
  EXPECT_TRUE(fails_with(minimal_scene_plus("dilated_polyhedron_contact: {merge_distance: -1}\n"),
                         14, "dilated_polyhedron_contact.merge_distance",
                         "expected a fraction of the dilation radius in [0, 2]"));
}

// A level-set shape from a superquadric: its mesh (8000 nodes by default), the grid spacing a
// fortieth of the mesh's smallest extent, the points two grid spacings apart, padding 2; each can
// be given, and values out of range are refused with the key's path.
TEST(SceneLevelSets, ShapeKeysAreReadWithTheirDefaults) {
  const std::string entry = "shapes:\n  - name: grain\n    level_set: {superquadric: {a: 0.002, "
                            "b: 0.0015, c: 0.001, n1: 2, n2: 4}";
  const SceneConfig scene = load_text(minimal_scene_plus(entry + "}\n"));
  const auto& shape = kdem::level_set_parameters(scene.shapes.at(0));
  EXPECT_EQ(shape.triangles.size(), 2u * 8000 - 4);
  EXPECT_NEAR(shape.grid_spacing, 2 * shape.smallest_size() / 40, 1e-18);
  EXPECT_LT(std::fabs(shape.smallest_size() - 0.001), 1e-5); // the lattice's nodes reach +-c
  EXPECT_EQ(shape.point_spacing, 2 * shape.grid_spacing);
  EXPECT_EQ(shape.padding, 2);
  const SceneConfig given = load_text(minimal_scene_plus(
      entry + ", nodes: 300, grid_spacing: 1.0e-4, padding: 3, point_spacing: 2.0e-4}\n"));
  const auto& chosen = kdem::level_set_parameters(given.shapes.at(0));
  EXPECT_EQ(chosen.triangles.size(), 2u * 300 - 4);
  EXPECT_EQ(chosen.grid_spacing, 1e-4);
  EXPECT_EQ(chosen.padding, 3);
  EXPECT_EQ(chosen.point_spacing, 2e-4);
  EXPECT_TRUE(fails_with(
      minimal_scene_plus(entry + ", grid_spacing: 0.01}\n"), 16, "shapes[0].level_set.grid_spacing",
      "expected a spacing in m between 1e-3 and 1 of the mesh's smallest extent"));
  EXPECT_TRUE(fails_with(minimal_scene_plus(entry + ", padding: 0}\n"), 16,
                         "shapes[0].level_set.padding", "padding"));
  EXPECT_TRUE(fails_with(minimal_scene_plus(entry + ", dilation_radius: 0.001}\n"), 16,
                         "shapes[0].level_set.dilation_radius", "got the key"));
  const SceneConfig counted = load_text(minimal_scene_plus(entry + ", point_count: 1500}\n"));
  EXPECT_EQ(kdem::level_set_parameters(counted.shapes.at(0)).point_count, 1500);
  EXPECT_EQ(shape.point_count, 0);
  EXPECT_TRUE(
      fails_with(minimal_scene_plus(entry + ", point_count: 1500, point_spacing: 2.0e-4}\n"), 16,
                 "shapes[0].level_set.point_count", "not both"));
  EXPECT_TRUE(fails_with(minimal_scene_plus(entry + ", point_count: 3}\n"), 16,
                         "shapes[0].level_set.point_count", "3"));
}

TEST(SceneLevelSets, ContactSettingsAreReadAndChecked) {
  const SceneConfig scene = load_text(minimal_scene_plus(
      "level_set_contact: {merge_distance: 0.25, averaging: summed, averaging_angle: 20, "
      "points: one_way}\n"));
  const auto& settings =
      dynamic_cast<const kdem::LevelSetContactConfig&>(*scene.family_settings.at("level_set"));
  EXPECT_EQ(settings.merge_distance, 0.25);
  EXPECT_FALSE(settings.averaging);
  EXPECT_EQ(settings.averaging_angle, 20);
  EXPECT_FALSE(settings.both_ways);
  const kdem::LevelSetContactConfig defaults;
  EXPECT_TRUE(defaults.both_ways);
  EXPECT_EQ(defaults.merge_distance, 0.5);
  EXPECT_TRUE(fails_with(minimal_scene_plus("level_set_contact: {points: three_ways}\n"), 14,
                         "level_set_contact.points", "three_ways"));
}

// A true/false key of superquadric_contact: on by default, off when set false, and anything
// else refused with the key's path.
void expect_switch_on_by_default(const std::string& key,
                                 bool kdem::SuperquadricContactConfig::*field) {
  EXPECT_TRUE(kdem::superquadric_contact(load_text(minimal_scene())).*field) << key;
  const SceneConfig scene =
      load_text(minimal_scene_plus("superquadric_contact: {" + key + ": false}\n"));
  EXPECT_FALSE(kdem::superquadric_contact(scene).*field) << key;
  EXPECT_TRUE(fails_with(minimal_scene_plus("superquadric_contact: {" + key + ": yes2}\n"), 14,
                         "superquadric_contact." + key, "expected true or false"));
}

TEST(SceneShapes, SeparationCertificatesAreOnByDefaultAndCanBeTurnedOff) {
  expect_switch_on_by_default("separation_certificates",
                              &kdem::SuperquadricContactConfig::separation_certificates);
}

TEST(SceneShapes, BoxCertificatesAreOnByDefaultAndCanBeTurnedOff) {
  expect_switch_on_by_default("box_certificates",
                              &kdem::SuperquadricContactConfig::box_certificates);
}

TEST(SceneShapes, ExtrapolatedNewtonStartsAreOnByDefaultAndCanBeTurnedOff) {
  expect_switch_on_by_default("extrapolate_start",
                              &kdem::SuperquadricContactConfig::extrapolate_start);
}

TEST(SceneShapes, TheEllipsoidScalarRootIsOnByDefaultAndCanBeTurnedOff) {
  expect_switch_on_by_default("ellipsoid_scalar_root",
                              &kdem::SuperquadricContactConfig::ellipsoid_scalar_root);
}

TEST(SceneShapes, SuperquadricLanesAreOnByDefaultAndCanBeTurnedOff) {
  expect_switch_on_by_default("lanes", &kdem::SuperquadricContactConfig::lanes);
}

TEST(SceneKeys, SortByCellIsOnByDefault) {
  EXPECT_TRUE(load_text(minimal_scene()).sort_by_cell);
  EXPECT_FALSE(load_text(minimal_scene_plus("sort_by_cell: false\n")).sort_by_cell);
  EXPECT_TRUE(fails_with(minimal_scene_plus("sort_by_cell: 3\n"), 14, "sort_by_cell",
                         "expected true or false"));
}

TEST(SceneShapes, NarrowPhaseLayoutKeys) {
  const SceneConfig defaults = load_text(minimal_scene());
  EXPECT_TRUE(kdem::superquadric_contact(defaults).compact_candidates);
  EXPECT_EQ(kdem::superquadric_contact(defaults).team_size, 0);
  const SceneConfig scene = load_text(
      minimal_scene_plus("superquadric_contact: {compact_candidates: false, team_size: 64}\n"));
  EXPECT_FALSE(kdem::superquadric_contact(scene).compact_candidates);
  EXPECT_EQ(kdem::superquadric_contact(scene).team_size, 64);
  EXPECT_TRUE(fails_with(minimal_scene_plus("superquadric_contact: {team_size: -1}\n"), 14,
                         "superquadric_contact.team_size", "expected"));
}

TEST(SceneOrientation, FixedOrientationIsNormalisedAndTurnsRandomOff) {
  const SceneConfig scene = load_text(
      minimal_scene_plus("    orientation: [2, 0, 0, 2]\n    angular_velocity: [0, 3, 0.5]\n"));
  EXPECT_FALSE(scene.sources[0].random_orientation);
  EXPECT_DOUBLE_EQ(scene.sources[0].orientation[0], std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(scene.sources[0].orientation[3], std::sqrt(0.5));
  EXPECT_EQ(scene.sources[0].angular_velocity, (kdem::Vec3d{0, 3, 0.5}));
}

TEST(SceneOrientation, FixedAndRandomTogether) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("    random_orientation: true\n"
                                            "    orientation: [1, 0, 0, 0]\n"),
                         15, "particles[0].orientation", "random_orientation is true"));
}

TEST(SceneOrientation, ZeroQuaternion) {
  EXPECT_TRUE(fails_with(minimal_scene_plus("    orientation: [0, 0, 0, 0]\n"), 14,
                         "particles[0].orientation",
                         "expected a quaternion [w, x, y, z] of non-zero length"));
}

} // namespace

namespace {

TEST(SourceTags, ATagIsReadAndNoneIsTheDefault) {
  EXPECT_EQ(load_text(minimal_scene()).sources.at(0).tag, "");
  const SceneConfig tagged =
      load_text(minimal_scene_with(13, "    count: 100\n    tag: tracer red"));
  EXPECT_EQ(tagged.sources.at(0).tag, "tracer red");
}

TEST(SourceTags, AnEmptyOrStructuredTagIsRefused) {
  EXPECT_TRUE(fails_with(minimal_scene_with(13, "    count: 100\n    tag: \"\""), 14,
                         "particles[0].tag", "a tag"));
  EXPECT_TRUE(fails_with(minimal_scene_with(13, "    count: 100\n    tag: [a, b]"), 14,
                         "particles[0].tag", "a tag"));
}

} // namespace
