#pragma once
// Reading and validating YAML scene files (reference: docs/scene.md).
#include <stdexcept>
#include <string>

#include "scene.hpp"

namespace kdem {

namespace scene_yaml {
class Value;
}

// A scene file that cannot be used. what() reads
//   FILE:LINE:COL: KEY.PATH: expected ..., got ...
// with 1-based line and column; errors about the file as a whole (missing, unreadable) carry no
// position and read "FILE: ...".
class SceneError : public std::runtime_error {
public:
  SceneError(const std::string& message, int line, int column, std::string key_path);
  explicit SceneError(const std::string& message);

  int line() const { return line_; }     // 1-based; 0 when the error has no position
  int column() const { return column_; } // 1-based; 0 when the error has no position
  const std::string& key_path() const { return key_path_; } // e.g. "walls[2].cylinder.radius"

private:
  int line_ = 0;
  int column_ = 0;
  std::string key_path_;
};

// Reads the scene file at `path`. Relative mesh files are resolved against the scene file's
// folder. Throws SceneError on the first problem found; a returned scene is fully validated.
SceneConfig load_scene(const std::string& path);

// As load_scene, for YAML text held in memory: `display_name` stands for the file in messages and
// in SceneConfig::source_file, `base_dir` is the folder relative mesh files are resolved against.
SceneConfig load_scene_from_string(const std::string& yaml_text, const std::string& display_name,
                                   const std::string& base_dir);

// The absolute path of the existing STL or OBJ file that a scene value names (relative paths
// from the scene file's folder); a SceneError at the value where there is none.
std::string existing_mesh_file(const scene_yaml::Value& value);

} // namespace kdem
