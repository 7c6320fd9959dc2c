// glTF 2.0 models in and out, through tinygltf (PNG and JPEG textures decoded by OpenCV).
//
// Loading flattens the default scene (or, without scenes, every mesh) into a holo::Model: every
// primitive of every mesh instance becomes one TriangleMesh with the node hierarchy's transforms
// applied (positions in metres, +Y up as glTF), normals computed when the file has none, uvs
// kept (TEXCOORD_0), triangle strips and fans converted to triangle lists. Materials keep the
// metallic-roughness factors, the emissive factor (times KHR_materials_emissive_strength) and
// the base-colour / metallic-roughness textures decoded to cv::Mat (BGR or BGRA, 8 bits).
//
// Errors are holo::InputError naming the file and the glTF field: unreadable or missing buffers,
// accessors that overrun their buffer, indices out of range, primitives that are not triangles
// (points, lines), sparse accessors, and Draco-compressed meshes (KHR_draco_mesh_compression in
// extensionsRequired), which this build cannot decode.
//
// Limits (InputError above them, checked before the data is allocated): the file, the triangles
// and vertices of the whole scene with every node instance counted, the node instances, and each
// texture's side. At the limits the loaded model holds at most 4M x 12 B of triangles and
// 12M x 32 B of vertex data (~0.45 GB) besides the file's own bytes; a relic shown on four
// 320x320 views needs far less (the bundled relics have under 70k triangles).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "holo/core/mesh.hpp"

namespace holo {

inline constexpr std::size_t kMaxGltfFileBytes = std::size_t{512} << 20;
inline constexpr std::size_t kMaxGltfTriangles = 4'000'000;
inline constexpr std::size_t kMaxGltfVertices = 12'000'000;
inline constexpr std::size_t kMaxGltfNodeVisits = 100'000;
inline constexpr int kMaxGltfTextureSide = 8192;

// Loads `.gltf` or `.glb` (chosen by extension).
Model loadGltf(const std::filesystem::path& path);
// Loads a binary glTF held in memory; `origin` stands in for the file name in errors.
Model loadGlbFromMemory(const std::vector<std::uint8_t>& glb, const std::string& origin);

// Writes `.glb` or `.gltf` (buffers and images embedded, so one file) atomically: a crash never
// leaves half a model. Textures are stored as PNG. Emission above 1 uses
// KHR_materials_emissive_strength.
void saveGltf(const std::filesystem::path& path, const Model& model);
// The same model as binary glTF bytes.
std::vector<std::uint8_t> encodeGlb(const Model& model);

}  // namespace holo
