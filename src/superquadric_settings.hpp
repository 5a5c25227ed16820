#pragma once
// The device form of a scene's superquadric narrow-phase settings (defined in
// superquadric_setup.cpp), shared by the families whose contacts the superquadric Newton solves.
#include "../kernels/superquadric/family.hpp"
#include "scene.hpp"

namespace kdem {

// The settings a scene gives (null: none, the defaults) as the kernels read them.
SuperquadricContactSettings superquadric_device_settings(const FamilySettings* scene_settings);

} // namespace kdem
