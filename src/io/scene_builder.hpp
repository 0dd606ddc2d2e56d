#pragma once
// Turns a scene description into a World: makes or reads each cloth's mesh, places it, lumps
// masses, builds springs and resolves pins. Throws SceneError (naming the scene file and the
// JSON path) for pins out of range, missing or malformed OBJ files and the like.
#include "sim/scene_desc.hpp"
#include "sim/world.hpp"

namespace weft {

World build_world(const SceneDesc& scene);

}  // namespace weft
