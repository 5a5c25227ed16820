#pragma once
// The scene readers of the shape families: how an entry of `shapes` names its family (by a key
// that holds the family's parameters) and which top-level key holds the family's settings.
// The scene loader reads `shapes` and those keys through this list alone.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "scene.hpp"
#include "scene_yaml.hpp"

namespace kdem {

struct FamilyScene {
  std::string name;         // the key of a `shapes` entry that makes a shape of this family
  std::string settings_key; // top-level scene key of the family's settings; empty: none
  std::function<std::shared_ptr<const FamilyShapeParameters>(const scene_yaml::Value&)> read_shape;
  std::function<std::shared_ptr<const FamilySettings>(const scene_yaml::Value&)> read_settings;
};

// Every family whose particles a scene can define under `shapes` (src/family_scenes.cpp). The
// engine checks at setup that each family of the device registry with shapes is listed here.
const std::vector<FamilyScene>& family_scenes();

} // namespace kdem
