#include "vtk_output.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "atomic_file.hpp"

namespace kdem {

namespace fs = std::filesystem;

namespace {

// Collects VTK error messages of one writer, so that they go into our exception instead of
// VTK's output window.
class VtkErrorCollector : public vtkCommand {
public:
  static VtkErrorCollector* New() { return new VtkErrorCollector; }
  // VTK's text reads "ERROR: In <source>, line <n>\n<class> (<address>): <message>\n\n".
  void Execute(vtkObject*, unsigned long, void* call_data) override {
    if (call_data == nullptr) {
      return;
    }
    std::string text = static_cast<const char*>(call_data);
    const std::size_t message_start = text.find("): ");
    if (message_start != std::string::npos) {
      text.erase(0, message_start + 3);
    }
    text.erase(text.find_last_not_of('\n') + 1);
    messages += (messages.empty() ? "" : "; ") + text;
  }
  std::string messages;
};

std::runtime_error write_error(const fs::path& path, const std::string& reason) {
  return std::runtime_error("cannot write '" + path.string() + "': " + reason);
}

void check_length(const fs::path& path, const char* field, std::size_t actual, std::size_t per_item,
                  std::size_t item_count, const char* items) {
  if (actual != per_item * item_count) {
    throw write_error(path, std::string(field) + " has " + std::to_string(actual) +
                                " values, expected " + std::to_string(per_item) + " per " + items +
                                " for " + std::to_string(item_count) + " " + items + "s");
  }
}

void check_particle_lengths(const fs::path& path, const ParticleSnapshot& snapshot) {
  const std::size_t count = snapshot.size();
  check_length(path, "position", snapshot.position.size(), 3, count, "particle");
  check_length(path, "velocity", snapshot.velocity.size(), 3, count, "particle");
  check_length(path, "angular_velocity", snapshot.angular_velocity.size(), 3, count, "particle");
  check_length(path, "quaternion", snapshot.quaternion.size(), 4, count, "particle");
  check_length(path, "shape", snapshot.shape.size(), 1, count, "particle");
  check_length(path, "material", snapshot.material.size(), 1, count, "particle");
  check_length(path, "id", snapshot.id.size(), 1, count, "particle");
  if (!snapshot.source.empty() || !snapshot.tag.empty()) {
    check_length(path, "source", snapshot.source.size(), 1, count, "particle");
    check_length(path, "tag", snapshot.tag.size(), 1, count, "particle");
  }
  for (const ShapeField& field : snapshot.shape_fields)
    check_length(path, field.name.c_str(), field.values.size(), std::size_t(field.components),
                 count, "particle");
}

// Every particle's shape has a surface, and every surface's triangles index its points.
void check_shape_surfaces(const fs::path& path, const ParticleSnapshot& snapshot) {
  for (std::size_t i = 0; i < snapshot.size(); ++i)
    if (snapshot.shape[i] < 0 || std::size_t(snapshot.shape[i]) >= snapshot.shape_surfaces.size())
      throw write_error(path, "particle " + std::to_string(i) + " has shape " +
                                  std::to_string(snapshot.shape[i]) + ", outside the " +
                                  std::to_string(snapshot.shape_surfaces.size()) +
                                  " shape surfaces of the snapshot");
  for (std::size_t k = 0; k < snapshot.shape_surfaces.size(); ++k) {
    const BodySurface& surface = snapshot.shape_surfaces[k];
    const std::size_t points = surface.points.size() / 3;
    for (int index : surface.triangles)
      if (index < 0 || std::size_t(index) >= points || surface.points.size() % 3 != 0)
        throw write_error(path, "the surface of shape " + std::to_string(k) +
                                    " has a triangle corner outside its " + std::to_string(points) +
                                    " points");
  }
}

// The body-frame surface of particle i (scaled by its radius for shape 0, the unit sphere),
// posed by its position and quaternion: v' = v + 2w (u x v) + 2 u x (u x v), u = (qx, qy, qz).
void append_posed_surface(const ParticleSnapshot& s, std::size_t i, const BodySurface& surface,
                          std::vector<double>& points) {
  const double scale = s.shape[i] == 0 ? s.radius[i] : 1.0;
  const double qw = s.quaternion[4 * i], qx = s.quaternion[4 * i + 1], qy = s.quaternion[4 * i + 2],
               qz = s.quaternion[4 * i + 3];
  for (std::size_t k = 0; k + 2 < surface.points.size(); k += 3) {
    const double x = scale * surface.points[k], y = scale * surface.points[k + 1],
                 z = scale * surface.points[k + 2];
    const double tx = 2 * (qy * z - qz * y), ty = 2 * (qz * x - qx * z), tz = 2 * (qx * y - qy * x);
    points.push_back(s.position[3 * i] + x + qw * tx + (qy * tz - qz * ty));
    points.push_back(s.position[3 * i + 1] + y + qw * ty + (qz * tx - qx * tz));
    points.push_back(s.position[3 * i + 2] + z + qw * tz + (qx * ty - qy * tx));
  }
}

template <class VtkArray, class Value>
vtkSmartPointer<VtkArray> make_array(const char* name, int components,
                                     const std::vector<Value>& values) {
  auto array = vtkSmartPointer<VtkArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size() / components));
  std::copy(values.begin(), values.end(), array->GetPointer(0));
  return array;
}

vtkSmartPointer<vtkPoints> make_points(const std::vector<double>& coordinates) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(make_array<vtkDoubleArray>("Points", 3, coordinates));
  return points;
}

// Cells of equal size whose point indices are listed in connectivity.
vtkSmartPointer<vtkCellArray> make_uniform_cells(vtkIdType points_per_cell,
                                                 const std::vector<vtkIdType>& connectivity) {
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->SetData(points_per_cell, make_array<vtkIdTypeArray>("connectivity", 1, connectivity));
  return cells;
}

void add_time_field_data(vtkDataObject* data, double time, std::int64_t step) {
  data->GetFieldData()->AddArray(make_array<vtkDoubleArray>("TimeValue", 1, std::vector{time}));
  data->GetFieldData()->AddArray(
      make_array<vtkTypeInt64Array>("step", 1, std::vector<std::int64_t>{step}));
}

void write_with_xml_writer(vtkXMLWriter* writer, vtkDataObject* data, const fs::path& path) {
  PendingFile pending(path);
  auto errors = vtkSmartPointer<VtkErrorCollector>::New();
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  // The pipeline repeats the writer's failure as a long request dump: keep it off the console.
  auto pipeline_errors = vtkSmartPointer<VtkErrorCollector>::New();
  writer->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline_errors);
  writer->SetInputData(data);
  writer->SetFileName(pending.temporary().string().c_str());
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToZLib();
  writer->SetHeaderTypeToUInt64(); // array sizes above 4 GiB
  if (writer->Write() != 1 || writer->GetErrorCode() != 0 || !errors->messages.empty()) {
    throw write_error(path, "VTK writer failed" +
                                (errors->messages.empty() ? "" : ": " + errors->messages));
  }
  pending.commit();
}

std::vector<vtkIdType> checked_triangle_connectivity(const fs::path& path,
                                                     const WallSurface& wall) {
  const auto point_count = static_cast<std::int64_t>(wall.points.size() / 3);
  std::vector<vtkIdType> connectivity(wall.triangles.begin(), wall.triangles.end());
  for (std::size_t i = 0; i < connectivity.size(); ++i) {
    if (connectivity[i] < 0 || connectivity[i] >= point_count) {
      throw write_error(path, "wall '" + wall.name + "' triangle " + std::to_string(i / 3) +
                                  " refers to point " + std::to_string(connectivity[i]) + " of " +
                                  std::to_string(point_count));
    }
  }
  return connectivity;
}

std::string shortest_decimal(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string xml_attribute_escaped(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
    case '&':
      escaped += "&amp;";
      break;
    case '<':
      escaped += "&lt;";
      break;
    case '>':
      escaped += "&gt;";
      break;
    case '"':
      escaped += "&quot;";
      break;
    case '\'':
      escaped += "&apos;";
      break;
    default:
      escaped += c;
    }
  }
  return escaped;
}

} // namespace

namespace {
vtkSmartPointer<vtkStringArray> string_array(const std::string& name,
                                             const std::vector<std::string>& values) {
  auto array = vtkSmartPointer<vtkStringArray>::New();
  array->SetName(name.c_str());
  for (const std::string& value : values)
    array->InsertNextValue(value);
  return array;
}
} // namespace

void write_particles_vtu(const fs::path& path, const ParticleSnapshot& snapshot) {
  check_particle_lengths(path, snapshot);
  std::vector<vtkIdType> point_of_vertex(snapshot.size());
  for (std::size_t i = 0; i < point_of_vertex.size(); ++i) {
    point_of_vertex[i] = static_cast<vtkIdType>(i);
  }

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(make_points(snapshot.position));
  grid->SetCells(VTK_VERTEX, make_uniform_cells(1, point_of_vertex));
  vtkPointData* point_data = grid->GetPointData();
  point_data->AddArray(make_array<vtkDoubleArray>("velocity", 3, snapshot.velocity));
  point_data->AddArray(
      make_array<vtkDoubleArray>("angular_velocity", 3, snapshot.angular_velocity));
  point_data->AddArray(make_array<vtkDoubleArray>("quaternion", 4, snapshot.quaternion));
  point_data->AddArray(make_array<vtkDoubleArray>("radius", 1, snapshot.radius));
  point_data->AddArray(make_array<vtkIntArray>("shape", 1, snapshot.shape));
  point_data->AddArray(make_array<vtkIntArray>("material", 1, snapshot.material));
  point_data->AddArray(make_array<vtkTypeInt64Array>("id", 1, snapshot.id));
  for (const ShapeField& field : snapshot.shape_fields)
    point_data->AddArray(
        make_array<vtkDoubleArray>(field.name.c_str(), field.components, field.values));
  if (!snapshot.source.empty()) {
    point_data->AddArray(make_array<vtkIntArray>("source", 1, snapshot.source));
    point_data->AddArray(make_array<vtkIntArray>("tag", 1, snapshot.tag));
    grid->GetFieldData()->AddArray(string_array("source_names", snapshot.source_names));
    grid->GetFieldData()->AddArray(string_array("tag_names", snapshot.tag_names));
  }
  add_time_field_data(grid, snapshot.time, snapshot.step);

  write_with_xml_writer(vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New(), grid, path);
}

void write_particle_surfaces_vtp(const fs::path& path, const ParticleSnapshot& snapshot) {
  check_particle_lengths(path, snapshot);
  if (snapshot.size() > 0 && snapshot.shape_surfaces.empty())
    throw write_error(path, "the snapshot has no particle shapes");
  check_shape_surfaces(path, snapshot);
  std::vector<double> points;
  std::vector<vtkIdType> triangles;
  std::vector<std::int64_t> point_id;
  std::vector<int> point_shape;
  for (std::size_t i = 0; i < snapshot.size(); ++i) {
    const BodySurface& body = snapshot.shape_surfaces[snapshot.shape[i]];
    const vtkIdType first = vtkIdType(points.size() / 3);
    for (int corner : body.triangles)
      triangles.push_back(first + corner);
    append_posed_surface(snapshot, i, body, points);
    point_id.insert(point_id.end(), body.points.size() / 3, snapshot.id[i]);
    point_shape.insert(point_shape.end(), body.points.size() / 3, snapshot.shape[i]);
  }
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  surface->SetPoints(make_points(points));
  surface->SetPolys(make_uniform_cells(3, triangles));
  surface->GetPointData()->AddArray(make_array<vtkTypeInt64Array>("id", 1, point_id));
  surface->GetPointData()->AddArray(make_array<vtkIntArray>("shape", 1, point_shape));
  add_time_field_data(surface, snapshot.time, snapshot.step);
  write_with_xml_writer(vtkSmartPointer<vtkXMLPolyDataWriter>::New(), surface, path);
}

void write_wall_vtp(const fs::path& path, const WallSurface& wall) {
  check_length(path, "wall points", wall.points.size(), 3, wall.points.size() / 3, "point");
  check_length(path, "wall triangles", wall.triangles.size(), 3, wall.triangles.size() / 3,
               "triangle");
  const std::vector<vtkIdType> connectivity = checked_triangle_connectivity(path, wall);

  auto surface = vtkSmartPointer<vtkPolyData>::New();
  surface->SetPoints(make_points(wall.points));
  surface->SetPolys(make_uniform_cells(3, connectivity));
  surface->GetFieldData()->AddArray(string_array("name", {wall.name}));

  write_with_xml_writer(vtkSmartPointer<vtkXMLPolyDataWriter>::New(), surface, path);
}

std::string pvd_collection_text(const std::vector<PvdSeries::Entry>& entries) {
  std::string text = "<?xml version=\"1.0\"?>\n"
                     "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                     "  <Collection>\n";
  for (const PvdSeries::Entry& entry : entries) {
    text += "    <DataSet timestep=\"" + shortest_decimal(entry.time) + "\" group=\"\" part=\"" +
            std::to_string(entry.part) + "\" file=\"" + xml_attribute_escaped(entry.relative_file) +
            "\"/>\n";
  }
  text += "  </Collection>\n</VTKFile>\n";
  return text;
}

PvdSeries::PvdSeries(fs::path directory, std::string basename)
    : directory_(std::move(directory)), basename_(std::move(basename)) {
  if (basename_.empty()) {
    throw std::invalid_argument("PvdSeries in '" + directory_.string() + "': empty basename");
  }
}

fs::path PvdSeries::path() const {
  return directory_ / (basename_ + ".pvd");
}

void PvdSeries::add(double time, const std::string& relative_file, int part) {
  add_entries(time, {{time, part, relative_file}});
}

void PvdSeries::add_parts(double time, const std::vector<std::string>& relative_files) {
  std::vector<Entry> new_entries;
  for (std::size_t part = 0; part < relative_files.size(); ++part) {
    new_entries.push_back({time, static_cast<int>(part), relative_files[part]});
  }
  add_entries(time, new_entries);
}

// Entries are only kept once the file listing them has been written.
void PvdSeries::add_entries(double time, const std::vector<Entry>& new_entries) {
  if (!std::isfinite(time)) {
    throw std::invalid_argument("cannot add to '" + path().string() + "': time is not finite");
  }
  const std::size_t old_size = entries_.size();
  entries_.insert(entries_.end(), new_entries.begin(), new_entries.end());
  try {
    write();
  } catch (...) {
    entries_.resize(old_size);
    throw;
  }
}

void PvdSeries::write() const {
  write_text_atomically(path(), pvd_collection_text(entries_));
}

} // namespace kdem
