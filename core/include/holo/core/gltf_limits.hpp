// The limits a glTF file is held to before its data is allocated (gltf_io.hpp says why they
// are where they are): InputError above any of them.
#pragma once

#include <cstddef>

namespace holo {

inline constexpr std::size_t kMaxGltfFileBytes = std::size_t{512} << 20;  // the file, bytes
inline constexpr std::size_t kMaxGltfTriangles = 4'000'000;  // the whole scene, every node instance counted
inline constexpr std::size_t kMaxGltfVertices = 12'000'000;  // likewise
inline constexpr std::size_t kMaxGltfNodeVisits = 100'000;   // node instances
inline constexpr int kMaxGltfTextureSide = 8192;             // pixels, each texture's side

}  // namespace holo
