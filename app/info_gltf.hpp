// `holopyramid info` for glTF models (.gltf, .glb): meshes, triangles, materials, bounds.
#pragma once

#include <filesystem>

namespace holo::app {

int describeGltf(const std::filesystem::path& path);

}  // namespace holo::app
