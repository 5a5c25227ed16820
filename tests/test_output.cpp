// Output layer: atomic files, HDF5 round trips, VTK frames and collections, CSV, run.json and
// the progress line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "atomic_file.hpp"
#include "body_surface.hpp"
#include "hdf5_io.hpp"
#include "progress.hpp"
#include "run_summary.hpp"
#include "series_csv.hpp"
#include "superquadric_scene.hpp"
#include "vtk_output.hpp"

namespace fs = std::filesystem;
using namespace kdem;

namespace {

// Each test gets an empty directory of its own, removed afterwards.
class OutputTest : public ::testing::Test {
protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    directory = fs::temp_directory_path() / ("kdem_test_output_" + std::to_string(::getpid()) +
                                             "_" + test->test_suite_name() + "_" + test->name());
    fs::remove_all(directory);
    fs::create_directories(directory);
  }
  void TearDown() override { fs::remove_all(directory); }

  fs::path directory;
};

std::vector<std::string> file_names_in(const fs::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(directory)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string read_text(const fs::path& path) {
  std::ifstream stream(path, std::ios::binary);
  std::stringstream content;
  content << stream.rdbuf();
  return content.str();
}

std::uint64_t bits_of(double value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

double double_with_bits(std::uint64_t bits) {
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// Runs body, expects a std::runtime_error whose message contains every one of the fragments.
template <class Body>
void expect_runtime_error_mentioning(Body body, const std::vector<std::string>& fragments) {
  try {
    body();
    ADD_FAILURE() << "no exception thrown";
  } catch (const std::runtime_error& error) {
    for (const std::string& fragment : fragments) {
      EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos)
          << "message '" << error.what() << "' does not mention '" << fragment << "'";
    }
  }
}

ParticleSnapshot three_particles() {
  ParticleSnapshot snapshot;
  snapshot.step = 123;
  snapshot.time = 0.00123;
  snapshot.position = {0, 0, 0, 1.5, -2.25, 3.125, 0.1, 0.2, 0.3};
  snapshot.velocity = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  snapshot.angular_velocity = {-1, -2, -3, -4, -5, -6, -7, -8, -9};
  snapshot.quaternion = {1, 0, 0, 0, 0.5, 0.5, 0.5, 0.5, 0, 1, 0, 0};
  snapshot.radius = {0.01, 0.02, 0.03};
  snapshot.shape = {0, 2, 5};
  snapshot.material = {1, 1, 3};
  snapshot.id = {7, std::int64_t{1} << 40, 9};
  return snapshot;
}

WallSurface unit_square_wall() {
  WallSurface wall;
  wall.name = "floor";
  wall.points = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  wall.triangles = {0, 1, 2, 0, 2, 3};
  return wall;
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Atomic files

TEST_F(OutputTest, AtomicWriteReplacesContentAndLeavesNoTemporaryFile) {
  const fs::path path = directory / "note.txt";
  write_text_atomically(path, "first\n");
  write_text_atomically(path, "second\n");
  EXPECT_EQ(read_text(path), "second\n");
  EXPECT_EQ(file_names_in(directory), std::vector<std::string>{"note.txt"});
}

TEST_F(OutputTest, AtomicWriteIntoMissingDirectoryThrowsAndLeavesNoFile) {
  const fs::path path = directory / "missing" / "note.txt";
  expect_runtime_error_mentioning([&] { write_text_atomically(path, "text"); }, {path.string()});
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(file_names_in(directory).empty());
}

TEST_F(OutputTest, TemporaryPathsAreHiddenUniqueAndBesideTheFinalFile) {
  const fs::path path = directory / "frame.vtu";
  const fs::path first = temporary_path_for(path);
  const fs::path second = temporary_path_for(path);
  EXPECT_EQ(first.parent_path(), directory);
  EXPECT_NE(first, second);
  EXPECT_EQ(first.filename().string().rfind(".frame.vtu.tmp", 0), 0u) << first;
}

TEST_F(OutputTest, FailedCommitRemovesTheTemporaryFile) {
  const fs::path final_path = directory / "missing" / "data.bin";
  const fs::path tmp = temporary_path_for(directory / "data.bin");
  write_text_atomically(tmp, "data");
  expect_runtime_error_mentioning([&] { commit_temporary(tmp, final_path); },
                                  {final_path.string()});
  EXPECT_FALSE(fs::exists(tmp));
  EXPECT_FALSE(fs::exists(final_path));
}

TEST_F(OutputTest, PendingFileNotCommittedRemovesItsTemporary) {
  const fs::path path = directory / "frame.vtu";
  {
    PendingFile pending(path);
    std::ofstream(pending.temporary()) << "half a frame";
    ASSERT_TRUE(fs::exists(pending.temporary()));
  }
  EXPECT_TRUE(file_names_in(directory).empty());
  {
    PendingFile pending(path);
    std::ofstream(pending.temporary()) << "whole frame";
    pending.commit();
  }
  EXPECT_EQ(read_text(path), "whole frame");
  EXPECT_EQ(file_names_in(directory), std::vector<std::string>{"frame.vtu"});
}

// ---------------------------------------------------------------------------------------------
// HDF5

TEST_F(OutputTest, Hdf5RoundTripIsBitExact) {
  const std::vector<double> doubles = {
      0.0,
      -0.0,
      std::numeric_limits<double>::quiet_NaN(),
      -std::numeric_limits<double>::quiet_NaN(),
      double_with_bits(0x7ff8000000000123ull), // NaN with a payload
      std::numeric_limits<double>::denorm_min(),
      -std::numeric_limits<double>::denorm_min(),
      double_with_bits(0x000fffffffffffffull), // largest subnormal
      std::numeric_limits<double>::min(),
      std::numeric_limits<double>::max(),
      std::numeric_limits<double>::lowest(),
      std::numeric_limits<double>::infinity(),
      -std::numeric_limits<double>::infinity(),
      0.1,
      1.0 / 3.0,
  };
  const std::vector<int> ints = {0, -1, std::numeric_limits<int>::min(),
                                 std::numeric_limits<int>::max()};
  const std::vector<std::int64_t> int64s = {std::numeric_limits<std::int64_t>::min(), -1,
                                            std::numeric_limits<std::int64_t>::max()};
  const std::vector<std::uint64_t> uint64s = {0, std::numeric_limits<std::uint64_t>::max()};
  const std::vector<double> positions = {1, 2, 3, 4, 5, 6};
  const std::string text = std::string("quote \" backslash \\ newline \n nul ") + '\0' +
                           " utf-8 \xc3\xa9 trailing nul" + '\0';
  const fs::path path = directory / "state.h5";
  {
    Hdf5Writer writer(path);
    writer.write("particles/state/special", doubles);
    writer.write("particles/position", positions, {2, 3});
    writer.write("ints", ints);
    writer.write("int64s", int64s);
    writer.write("uint64s", uint64s);
    writer.write("empty", std::vector<double>{});
    writer.write("no_rows", std::vector<int>{}, {0, 3});
    writer.write_scalar("time", -0.0);
    writer.write_scalar("step", std::numeric_limits<std::int64_t>::min());
    writer.write_scalar("seed", std::numeric_limits<std::uint64_t>::max());
    writer.write_scalar("count", 7);
    writer.write_string("meta/scene", text);
    writer.write_string("meta/empty", "");
    EXPECT_FALSE(fs::exists(path)) << "visible before close()";
    writer.close();
  }
  EXPECT_EQ(file_names_in(directory), std::vector<std::string>{"state.h5"});

  Hdf5Reader reader(path);
  const std::vector<double> read_back = reader.read_doubles("particles/state/special");
  ASSERT_EQ(read_back.size(), doubles.size());
  for (std::size_t i = 0; i < doubles.size(); ++i) {
    EXPECT_EQ(bits_of(read_back[i]), bits_of(doubles[i])) << "value " << i;
  }
  EXPECT_EQ(reader.read_doubles("/particles/position"), positions);
  EXPECT_EQ(reader.shape("particles/position"), (std::vector<hsize_t>{2, 3}));
  EXPECT_EQ(reader.read_ints("ints"), ints);
  EXPECT_EQ(reader.read_int64("int64s"), int64s);
  EXPECT_EQ(reader.read_uint64("uint64s"), uint64s);
  EXPECT_TRUE(reader.read_doubles("empty").empty());
  EXPECT_TRUE(reader.read_ints("no_rows").empty());
  EXPECT_EQ(reader.shape("no_rows"), (std::vector<hsize_t>{0, 3}));
  EXPECT_EQ(bits_of(reader.read_scalar_double("time")), bits_of(-0.0));
  EXPECT_EQ(reader.shape("time"), std::vector<hsize_t>{});
  EXPECT_EQ(reader.read_scalar_int64("step"), std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(reader.read_scalar_uint64("seed"), std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(reader.read_scalar_int64("count"), 7);
  EXPECT_EQ(reader.read_string("meta/scene"), text);
  EXPECT_EQ(reader.read_string("meta/empty"), "");

  EXPECT_TRUE(reader.has("particles"));
  EXPECT_TRUE(reader.has("particles/state/special"));
  EXPECT_TRUE(reader.has("/meta/scene"));
  EXPECT_FALSE(reader.has("particles/velocity"));
  EXPECT_FALSE(reader.has("nothing/here/at/all"));
}

TEST_F(OutputTest, Hdf5MissingDatasetErrorNamesDatasetAndFile) {
  const fs::path path = directory / "state.h5";
  {
    Hdf5Writer writer(path);
    writer.write("particles/position", std::vector<double>{1, 2, 3});
  }
  Hdf5Reader reader(path);
  expect_runtime_error_mentioning([&] { reader.read_doubles("particles/velocity"); },
                                  {"particles/velocity", path.string()});
  expect_runtime_error_mentioning([&] { reader.read_scalar_int64("missing/step"); },
                                  {"missing/step", path.string()});
}

TEST_F(OutputTest, Hdf5WrongTypeOrCountIsAnError) {
  const fs::path path = directory / "state.h5";
  {
    Hdf5Writer writer(path);
    writer.write("values", std::vector<double>{1, 2});
    writer.write("ids", std::vector<std::int64_t>{1, 2});
  }
  Hdf5Reader reader(path);
  expect_runtime_error_mentioning([&] { reader.read_ints("values"); },
                                  {"values", "64-bit floating point"});
  expect_runtime_error_mentioning([&] { reader.read_uint64("ids"); }, {"ids", "signed"});
  expect_runtime_error_mentioning([&] { reader.read_scalar_double("values"); },
                                  {"values", "2 values"});
  expect_runtime_error_mentioning([&] { reader.read_string("values"); }, {"string"});
}

TEST_F(OutputTest, Hdf5WriterRejectsBadShapesAndDuplicateNames) {
  Hdf5Writer writer(directory / "state.h5");
  EXPECT_THROW(writer.write("a", std::vector<double>{1, 2, 3}, {2, 2}), std::invalid_argument);
  writer.write("a", std::vector<double>{1});
  expect_runtime_error_mentioning([&] { writer.write("a", std::vector<double>{2}); }, {"'a'"});
}

TEST_F(OutputTest, Hdf5WriterAbandonedByAnExceptionLeavesNoFile) {
  const fs::path path = directory / "state.h5";
  try {
    Hdf5Writer writer(path);
    writer.write("a", std::vector<double>{1});
    throw std::runtime_error("simulated failure");
  } catch (const std::runtime_error&) {
  }
  EXPECT_TRUE(file_names_in(directory).empty());
}

TEST_F(OutputTest, Hdf5WriterDestroyedNormallyCommits) {
  const fs::path path = directory / "state.h5";
  { Hdf5Writer(path).write_scalar("x", 1.5); }
  EXPECT_EQ(Hdf5Reader(path).read_scalar_double("x"), 1.5);
}

TEST_F(OutputTest, Hdf5FileErrorsNameTheFile) {
  const fs::path unwritable = directory / "missing" / "state.h5";
  expect_runtime_error_mentioning([&] { Hdf5Writer writer(unwritable); }, {unwritable.string()});
  EXPECT_TRUE(file_names_in(directory).empty());
  const fs::path absent = directory / "absent.h5";
  expect_runtime_error_mentioning([&] { Hdf5Reader reader(absent); }, {absent.string()});
}

// ---------------------------------------------------------------------------------------------
// VTK

TEST_F(OutputTest, ParticleFrameReadsBackWithVtk) {
  const fs::path frames = directory / "frames";
  fs::create_directories(frames);
  const fs::path path = frames / "particles_000123.vtu";
  write_particles_vtu(path, three_particles());
  EXPECT_EQ(file_names_in(frames), std::vector<std::string>{"particles_000123.vtu"});
  EXPECT_NE(read_text(path).find("format=\"appended\""), std::string::npos);

  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_EQ(grid->GetNumberOfPoints(), 3);
  ASSERT_EQ(grid->GetNumberOfCells(), 3);
  EXPECT_EQ(grid->GetCellType(2), VTK_VERTEX);
  double point[3];
  grid->GetPoint(1, point);
  EXPECT_EQ(point[0], 1.5);
  EXPECT_EQ(point[1], -2.25);
  EXPECT_EQ(point[2], 3.125);

  vtkPointData* point_data = grid->GetPointData();
  vtkDataArray* velocity = point_data->GetArray("velocity");
  ASSERT_NE(velocity, nullptr);
  EXPECT_EQ(velocity->GetNumberOfComponents(), 3);
  EXPECT_EQ(velocity->GetComponent(2, 1), 8);
  vtkDataArray* quaternion = point_data->GetArray("quaternion");
  ASSERT_NE(quaternion, nullptr);
  EXPECT_EQ(quaternion->GetNumberOfComponents(), 4);
  EXPECT_EQ(quaternion->GetComponent(1, 3), 0.5);
  ASSERT_NE(point_data->GetArray("angular_velocity"), nullptr);
  EXPECT_EQ(point_data->GetArray("angular_velocity")->GetComponent(0, 2), -3);
  EXPECT_EQ(point_data->GetArray("radius")->GetComponent(2, 0), 0.03);
  EXPECT_EQ(point_data->GetArray("shape")->GetComponent(2, 0), 5);
  EXPECT_EQ(point_data->GetArray("material")->GetComponent(2, 0), 3);
  vtkDataArray* id = point_data->GetArray("id");
  ASSERT_NE(id, nullptr);
  EXPECT_EQ(id->GetDataTypeSize(), 8);
  EXPECT_EQ(static_cast<std::int64_t>(id->GetComponent(1, 0)), std::int64_t{1} << 40);
  vtkDataArray* time = grid->GetFieldData()->GetArray("TimeValue");
  ASSERT_NE(time, nullptr);
  EXPECT_EQ(time->GetComponent(0, 0), 0.00123);
}

TEST_F(OutputTest, EmptyParticleFrameIsValid) {
  const fs::path path = directory / "empty.vtu";
  write_particles_vtu(path, ParticleSnapshot{});
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
}

TEST_F(OutputTest, InconsistentSnapshotIsRefusedAndWritesNothing) {
  ParticleSnapshot snapshot = three_particles();
  snapshot.velocity.pop_back();
  const fs::path path = directory / "bad.vtu";
  expect_runtime_error_mentioning([&] { write_particles_vtu(path, snapshot); },
                                  {path.string(), "velocity"});
  EXPECT_TRUE(file_names_in(directory).empty());
}

TEST_F(OutputTest, VtuIntoMissingDirectoryThrowsAndLeavesNoFile) {
  const fs::path path = directory / "missing" / "particles.vtu";
  expect_runtime_error_mentioning([&] { write_particles_vtu(path, three_particles()); },
                                  {path.string()});
  EXPECT_TRUE(file_names_in(directory).empty());
}

// The three particles as a sphere, a cube-like and a cylinder-like superquadric (shape ids 0,
// 1, 2), with their semi-axes and exponents here (a sphere: a = b = c = r, n1 = n2 = 2).
const double shaped_half_axes[3][3] = {{0.01, 0.01, 0.01}, {0.02, 0.01, 0.005}, {0.01, 0.01, 0.03}};
const double shaped_blockiness[3][2] = {{2, 2}, {8, 8}, {8, 2}};
const int surface_resolution = 16;

ParticleSnapshot three_shaped_particles() {
  ParticleSnapshot snapshot = three_particles();
  snapshot.shape = {0, 1, 2};
  const double none = std::numeric_limits<double>::quiet_NaN();
  snapshot.shape_fields = {
      {"half_axes", 3, {none, none, none, 0.02, 0.01, 0.005, 0.01, 0.01, 0.03}},
      {"blockiness", 2, {none, none, 8, 8, 8, 2}}};
  snapshot.shape_surfaces = {unit_sphere_surface(surface_resolution)};
  for (int k = 1; k < 3; ++k)
    snapshot.shape_surfaces.push_back(superquadric_surface(
        {shaped_half_axes[k][0], shaped_half_axes[k][1], shaped_half_axes[k][2]},
        shaped_blockiness[k][0], shaped_blockiness[k][1], surface_resolution));
  return snapshot;
}

// Shape function of particle i of a snapshot at a world point (book Eq. 2.1, body frame).
double shape_function_at(const ParticleSnapshot& s, std::size_t i, const double world[3]) {
  double d[3] = {world[0] - s.position[3 * i], world[1] - s.position[3 * i + 1],
                 world[2] - s.position[3 * i + 2]};
  // body = conj(q) d: v' = v + 2w (u x v) + 2 u x (u x v) with u = -(qx, qy, qz)
  const double w = s.quaternion[4 * i], ux = -s.quaternion[4 * i + 1],
               uy = -s.quaternion[4 * i + 2], uz = -s.quaternion[4 * i + 3];
  const double tx = 2 * (uy * d[2] - uz * d[1]), ty = 2 * (uz * d[0] - ux * d[2]),
               tz = 2 * (ux * d[1] - uy * d[0]);
  const double x = d[0] + w * tx + (uy * tz - uz * ty), y = d[1] + w * ty + (uz * tx - ux * tz),
               z = d[2] + w * tz + (ux * ty - uy * tx);
  const double a = shaped_half_axes[i][0], b = shaped_half_axes[i][1], c = shaped_half_axes[i][2];
  const double n1 = shaped_blockiness[i][0], n2 = shaped_blockiness[i][1];
  return std::pow(std::pow(std::abs(x / a), n2) + std::pow(std::abs(y / b), n2), n1 / n2) +
         std::pow(std::abs(z / c), n1) - 1;
}

TEST_F(OutputTest, ShapedFrameCarriesSemiAxesAndBlockiness) {
  const fs::path path = directory / "shaped.vtu";
  write_particles_vtu(path, three_shaped_particles());
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPointData* point_data = reader->GetOutput()->GetPointData();
  ASSERT_NE(point_data->GetArray("half_axes"), nullptr);
  ASSERT_NE(point_data->GetArray("blockiness"), nullptr);
  EXPECT_EQ(point_data->GetArray("half_axes")->GetComponent(1, 2), 0.005);
  EXPECT_EQ(point_data->GetArray("blockiness")->GetComponent(2, 0), 8);
  EXPECT_EQ(point_data->GetArray("blockiness")->GetComponent(2, 1), 2);
  EXPECT_TRUE(std::isnan(point_data->GetArray("half_axes")->GetComponent(0, 0))); // the sphere
}

TEST_F(OutputTest, ParticleSurfacesLieOnTheTrueShapes) {
  const ParticleSnapshot snapshot = three_shaped_particles();
  const fs::path path = directory / "shapes.vtp";
  const int resolution = surface_resolution;
  write_particle_surfaces_vtp(path, snapshot);
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* surface = reader->GetOutput();
  const vtkIdType per_particle = resolution * (resolution / 2 + 1);
  ASSERT_EQ(surface->GetNumberOfPoints(), 3 * per_particle);
  EXPECT_EQ(surface->GetNumberOfPolys(), 3 * 2 * resolution * (resolution / 2));
  vtkDataArray* id = surface->GetPointData()->GetArray("id");
  ASSERT_NE(id, nullptr);
  double worst = 0;
  for (vtkIdType k = 0; k < surface->GetNumberOfPoints(); ++k) {
    const std::size_t particle = std::size_t(k / per_particle);
    EXPECT_EQ(static_cast<std::int64_t>(id->GetComponent(k, 0)), snapshot.id[particle]);
    double point[3];
    surface->GetPoint(k, point);
    worst = std::max(worst, std::abs(shape_function_at(snapshot, particle, point)));
  }
  // Points are exact on the surface up to rounding of the pose and the powers.
  EXPECT_LT(worst, 1e-9);
}

TEST_F(OutputTest, SurfacesRefuseAShapeWithoutSurfaceAndAStrayTriangle) {
  const fs::path path = directory / "shapes.vtp";
  ParticleSnapshot unknown_shape = three_shaped_particles();
  unknown_shape.shape[2] = 3;
  expect_runtime_error_mentioning([&] { write_particle_surfaces_vtp(path, unknown_shape); },
                                  {path.string(), "particle 2 has shape 3", "3 shape surfaces"});
  ParticleSnapshot stray = three_shaped_particles();
  stray.shape_surfaces[1].triangles.back() = int(stray.shape_surfaces[1].points.size() / 3);
  expect_runtime_error_mentioning([&] { write_particle_surfaces_vtp(path, stray); },
                                  {path.string(), "surface of shape 1", "outside"});
  EXPECT_TRUE(file_names_in(directory).empty());
}

TEST_F(OutputTest, SurfacesNeedShapes) {
  const fs::path path = directory / "shapes.vtp";
  expect_runtime_error_mentioning([&] { write_particle_surfaces_vtp(path, three_particles()); },
                                  {path.string(), "no particle shapes"});
  EXPECT_TRUE(file_names_in(directory).empty());
}

TEST_F(OutputTest, WallSurfaceReadsBackWithVtk) {
  const fs::path path = directory / "floor.vtp";
  write_wall_vtp(path, unit_square_wall());
  EXPECT_EQ(file_names_in(directory), std::vector<std::string>{"floor.vtp"});

  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* surface = reader->GetOutput();
  EXPECT_EQ(surface->GetNumberOfPoints(), 4);
  EXPECT_EQ(surface->GetNumberOfPolys(), 2);
  EXPECT_EQ(surface->GetCellType(1), VTK_TRIANGLE);
  double point[3];
  surface->GetPoint(2, point);
  EXPECT_EQ(point[0], 1);
  EXPECT_EQ(point[1], 1);
  auto* name = vtkStringArray::SafeDownCast(surface->GetFieldData()->GetAbstractArray("name"));
  ASSERT_NE(name, nullptr);
  EXPECT_EQ(name->GetValue(0), "floor");
}

TEST_F(OutputTest, WallWithOutOfRangeIndexIsRefused) {
  WallSurface wall = unit_square_wall();
  wall.triangles[4] = 4;
  const fs::path path = directory / "floor.vtp";
  expect_runtime_error_mentioning([&] { write_wall_vtp(path, wall); }, {path.string(), "floor"});
  EXPECT_TRUE(file_names_in(directory).empty());
}

TEST_F(OutputTest, PvdCollectionParsesAndListsEveryEntry) {
  PvdSeries walls(directory, "walls");
  walls.add(0.0, "frames/walls_000000_floor.vtp", 0);
  walls.add(0.0, "frames/walls_000000_lid.vtp", 1);
  walls.add(0.0025, "frames/walls_000001_a&b.vtp", 0);
  EXPECT_EQ(walls.path(), directory / "walls.pvd");
  EXPECT_EQ(file_names_in(directory), std::vector<std::string>{"walls.pvd"});

  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(walls.path().c_str());
  ASSERT_EQ(parser->Parse(), 1);
  vtkXMLDataElement* root = parser->GetRootElement();
  ASSERT_NE(root, nullptr);
  EXPECT_STREQ(root->GetName(), "VTKFile");
  EXPECT_STREQ(root->GetAttribute("type"), "Collection");
  vtkXMLDataElement* collection = root->FindNestedElementWithName("Collection");
  ASSERT_NE(collection, nullptr);
  ASSERT_EQ(collection->GetNumberOfNestedElements(), 3);
  vtkXMLDataElement* last = collection->GetNestedElement(2);
  EXPECT_STREQ(last->GetName(), "DataSet");
  EXPECT_EQ(std::strtod(last->GetAttribute("timestep"), nullptr), 0.0025);
  EXPECT_STREQ(last->GetAttribute("file"), "frames/walls_000001_a&b.vtp");
  EXPECT_STREQ(collection->GetNestedElement(1)->GetAttribute("part"), "1");

  EXPECT_THROW(walls.add(std::nan(""), "x.vtp"), std::invalid_argument);
  EXPECT_EQ(walls.entries().size(), 3u);

  walls.add_parts(0.005, {"frames/walls_000002_floor.vtp", "frames/walls_000002_lid.vtp"});
  ASSERT_EQ(walls.entries().size(), 5u);
  EXPECT_EQ(walls.entries()[4].part, 1);
  EXPECT_EQ(walls.entries()[4].time, 0.005);
  EXPECT_EQ(read_text(walls.path()), pvd_collection_text(walls.entries()));
}

TEST_F(OutputTest, PvdFramesOpenThroughTheCollection) {
  fs::create_directories(directory / "frames");
  PvdSeries particles(directory, "particles");
  write_particles_vtu(directory / "frames" / "particles_000123.vtu", three_particles());
  particles.add(0.00123, "frames/particles_000123.vtu");

  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(particles.path().c_str());
  ASSERT_EQ(parser->Parse(), 1);
  const char* file = parser->GetRootElement()
                         ->FindNestedElementWithName("Collection")
                         ->GetNestedElement(0)
                         ->GetAttribute("file");
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName((directory / file).c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 3);
}

// ---------------------------------------------------------------------------------------------
// CSV

TEST_F(OutputTest, CsvHasHeaderAndExactNumbers) {
  const fs::path path = directory / "series.csv";
  SeriesCsv series(path, {"step", "time", "kinetic energy, J"});
  series.add_row({100, 0.1, 1e-7});
  series.add_row({std::nan(""), std::numeric_limits<double>::infinity(), -0.0});
  series.add_row({9007199254740992.0, 1.0 / 3.0, -1.5e300});
  EXPECT_FALSE(fs::exists(path)) << "written before flush()";
  series.flush();
  EXPECT_EQ(file_names_in(directory), std::vector<std::string>{"series.csv"});
  const std::string third_value = csv_number(1.0 / 3.0);
  EXPECT_EQ(read_text(path), "step,time,\"kinetic energy, J\"\n"
                             "100,0.1,1e-07\n"
                             "nan,inf,-0\n"
                             "9007199254740992," +
                                 third_value + ",-1.5e+300\n");
  EXPECT_EQ(std::strtod(third_value.c_str(), nullptr), 1.0 / 3.0);
  EXPECT_EQ(series.row_count(), 3u);
  EXPECT_THROW(series.add_row({1, 2}), std::invalid_argument);

  series.add_row({101, 0.2, 3});
  series.flush();
  EXPECT_NE(read_text(path).find("\n101,0.2,3\n"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// run.json

TEST_F(OutputTest, RunJsonEscapesStringsAndWritesNullForNonFinite) {
  RunSummary summary;
  summary.version = "0.1 \"beta\" \\ \n\t\x01 \xc3\xa9";
  summary.git_hash = "abc123";
  summary.backend = "OpenMP";
  summary.threads = 8;
  summary.steps = 123456789012;
  summary.simulated_time = 0.1;
  summary.energy_drift = std::nan("");
  summary.wall_seconds = std::numeric_limits<double>::infinity();
  summary.extra = {{"lacey_index", 0.5}, {"undefined", -std::numeric_limits<double>::infinity()}};
  const std::string json = to_json(summary);

  const auto contains = [&](const std::string& fragment) {
    EXPECT_NE(json.find(fragment), std::string::npos) << "missing " << fragment << " in\n" << json;
  };
  contains(R"("version": "0.1 \"beta\" \\ \n\t\u0001 )"
           "\xc3\xa9\"");
  contains(R"("backend": "OpenMP",)");
  contains(R"("threads": 8,)");
  contains(R"("steps": 123456789012,)");
  contains(R"("simulated_time": 0.1,)");
  contains(R"("energy_drift": null,)");
  contains(R"("wall_seconds": null,)");
  contains("\"extra\": {\n    \"lacey_index\": 0.5,\n    \"undefined\": null\n  }\n}\n");
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.find("nan"), std::string::npos);
  EXPECT_EQ(json.find("inf"), std::string::npos);

  const fs::path path = directory / "run.json";
  write_run_json(path, summary);
  EXPECT_EQ(read_text(path), json);
  EXPECT_EQ(file_names_in(directory), std::vector<std::string>{"run.json"});
}

TEST(JsonNumber, IsShortestExactOrNull) {
  EXPECT_EQ(json_number(0.1), "0.1");
  EXPECT_EQ(json_number(-0.0), "-0");
  EXPECT_EQ(json_number(1e300), "1e+300");
  EXPECT_EQ(std::strtod(json_number(1.0 / 3.0).c_str(), nullptr), 1.0 / 3.0);
  EXPECT_EQ(json_number(std::nan("")), "null");
  EXPECT_EQ(json_string("a\"b"), "\"a\\\"b\"");
}

// ---------------------------------------------------------------------------------------------
// Progress line

namespace {

std::string everything_written_to(std::FILE* stream) {
  std::rewind(stream);
  std::string text;
  for (int c = std::fgetc(stream); c != EOF; c = std::fgetc(stream)) {
    text += static_cast<char>(c);
  }
  return text;
}

} // namespace

TEST(ProgressLineTest, FormatsDurationsAndLines) {
  EXPECT_EQ(format_duration(3723), "1:02:03");
  EXPECT_EQ(format_duration(5), "0:05");
  EXPECT_EQ(format_duration(-1), "--");
  EXPECT_EQ(format_progress(1200, 10000, 0.0012, 3.45e6, 65),
            "step 1200/10000 (12.0%)  t = 0.0012 s  3.45e+06 particle-steps/s  ETA 1:05");
  EXPECT_EQ(format_progress(5, 0, 1, 2, 3), "step 5  t = 1 s  2 particle-steps/s");
}

TEST(ProgressLineTest, LogModePrintsFirstUpdateAndFinalState) {
  std::FILE* stream = std::tmpfile();
  ASSERT_NE(stream, nullptr);
  {
    ProgressLine progress(false, 100, stream, false);
    progress.update(1, 0.001, 1e6);
    progress.update(2, 0.002, 1e6); // within 10 s of the first: not printed
    progress.finish();
  }
  const std::string text = everything_written_to(stream);
  std::fclose(stream);
  EXPECT_EQ(text.find('\r'), std::string::npos);
  ASSERT_NE(text.find("step 1/100"), std::string::npos) << text;
  ASSERT_NE(text.find("step 2/100"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2) << text;
}

TEST(ProgressLineTest, TerminalModeRewritesOneLine) {
  std::FILE* stream = std::tmpfile();
  ASSERT_NE(stream, nullptr);
  {
    ProgressLine progress(false, 100, stream, true);
    progress.update(1, 0.001, 1e6);
    progress.finish();
  }
  const std::string text = everything_written_to(stream);
  std::fclose(stream);
  EXPECT_EQ(text.front(), '\r');
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
}

TEST(ProgressLineTest, QuietPrintsNothing) {
  std::FILE* stream = std::tmpfile();
  ASSERT_NE(stream, nullptr);
  {
    ProgressLine progress(true, 100, stream, false);
    progress.update(1, 0.001, 1e6);
    progress.finish();
  }
  EXPECT_EQ(everything_written_to(stream), "");
  std::fclose(stream);
}
