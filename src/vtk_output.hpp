#pragma once
// ParaView output: particle frames (.vtu), wall surfaces (.vtp) and time-series collections
// (.pvd). Every file is written to a temporary name and renamed, so ParaView never reads a
// half-written frame.
#include <filesystem>
#include <string>
#include <vector>

#include "snapshot.hpp"

namespace kdem {

// One vertex cell per particle at its position. Point data: velocity (3), angular_velocity (3),
// quaternion (4, w x y z), radius, shape, material, id (Int64). Field data: TimeValue (s) and
// step. Binary appended, zlib-compressed. Throws std::runtime_error naming the file when the
// snapshot's arrays disagree in length or the file cannot be written.
// Also each of the snapshot's shape fields (e.g. half_axes (3) and blockiness (2)).
void write_particles_vtu(const std::filesystem::path& path, const ParticleSnapshot& snapshot);

// The surface of every particle of a snapshot that has shapes: its shape's body-frame surface
// (shape 0 scaled by the particle's radius), posed by position and quaternion. Point data: id
// and shape per surface point, so ParaView can colour or threshold by particle. Throws
// std::runtime_error naming the file for a snapshot without shapes, a particle whose shape has
// no surface, a triangle outside its surface's points, or a failed write.
void write_particle_surfaces_vtp(const std::filesystem::path& path,
                                 const ParticleSnapshot& snapshot);

// The wall's triangles as polydata; the wall's name is stored as field data "name". Throws
// std::runtime_error naming the file for out-of-range indices or a failed write.
void write_wall_vtp(const std::filesystem::path& path, const WallSurface& wall);

// A ParaView collection file <directory>/<basename>.pvd listing data files by time. Files are
// given relative to the directory, e.g. "frames/particles_000123.vtu". Several files with the
// same time and different parts (e.g. one per wall) are shown by ParaView as one multiblock.
class PvdSeries {
public:
  struct Entry {
    double time; // s
    int part;
    std::string relative_file;
  };

  PvdSeries(std::filesystem::path directory, std::string basename);

  // Appends an entry and rewrites the .pvd file atomically. Throws std::invalid_argument for a
  // non-finite time, std::runtime_error when the file cannot be written.
  void add(double time, const std::string& relative_file, int part = 0);
  // Adds one entry per file, part = index in relative_files, and rewrites the file once: for
  // several walls per frame, cheaper than one add() per wall.
  void add_parts(double time, const std::vector<std::string>& relative_files);
  void write() const;

  std::filesystem::path path() const; // <directory>/<basename>.pvd
  const std::vector<Entry>& entries() const { return entries_; }

private:
  void add_entries(double time, const std::vector<Entry>& new_entries);

  std::filesystem::path directory_;
  std::string basename_;
  std::vector<Entry> entries_;
};

// The .pvd file's text for these entries (what PvdSeries::write writes).
std::string pvd_collection_text(const std::vector<PvdSeries::Entry>& entries);

} // namespace kdem
