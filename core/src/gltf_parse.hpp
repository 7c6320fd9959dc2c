// glTF bytes into a tinygltf::Model (internal to core): the file-size limit, OpenCV texture
// decoding (gltf_textures.hpp), external files confined to the glTF's folder
// (gltf_confined_files.hpp), and tinygltf's failures as InputError naming the file and, where
// tinygltf's message tells, "buffers" or "images". A file that needs Draco is refused by name.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "gltf_tinygltf.hpp"

namespace holo::gltf_detail {

// The extension of `path`, lowercase: ".gltf" and ".glb" choose the format.
std::string formatExtension(const std::filesystem::path& path);

// A `.gltf` or `.glb` file (chosen by extension), at most kMaxGltfFileBytes.
tinygltf::Model parseGltfFile(const std::filesystem::path& path);
// Binary glTF held in memory; `origin` stands in for the file name in errors. Nothing external.
tinygltf::Model parseGlb(const std::vector<std::uint8_t>& glb, const std::string& origin);

}  // namespace holo::gltf_detail
