// glTF 2.0 models in and out, through tinygltf (PNG and JPEG textures decoded by OpenCV).
//
// Loading flattens the default scene (or, without scenes, every mesh) into a holo::Model: every
// primitive of every mesh instance becomes one TriangleMesh with the node hierarchy's transforms
// applied (positions in metres, +Y up as glTF), normals computed when the file has none,
// TEXCOORD_0 and TEXCOORD_1 kept, tangents kept or, where the file has none (or unusable ones)
// and the primitive has texture coordinates or a normal map, generated the MikkTSpace way from
// the normal map's uv set (TriangleMesh::computeTangents), triangle strips
// and fans converted to triangle lists. Materials keep every glTF 2.0 core property (factors,
// the five texture slots with texCoord, normal scale, occlusion strength, alphaMode and cutoff,
// doubleSided) and the extensions KHR_materials_emissive_strength, KHR_texture_transform,
// KHR_materials_specular, KHR_materials_clearcoat, KHR_materials_transmission,
// KHR_materials_volume and KHR_materials_ior. Textures are decoded once to 8 bits with their
// sampler and mip chain (holo::Texture).
//
// Nothing is dropped silently: an optional extension this build does not read is skipped with
// one warning per file and counted ("glTF/Optional extensions ignored"); so are undecodable
// images ("glTF/Textures ignored") and factors above their bound of 1, clamped ("glTF/Material
// factors clamped to 1").
//
// Errors are holo::InputError naming the file and the glTF field: unreadable or missing buffers,
// accessors that overrun their buffer, indices out of range, primitives that are not triangles
// (points, lines), sparse accessors, an extension in extensionsRequired that this build does not
// read (Draco-compressed meshes among them), texture indices out of range, texCoord other than 0
// or 1, and material factors that are NaN, infinite or negative (the field names the material),
// an attenuationDistance of 0 and an IOR below 1.
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

#include "holo/core/gltf_limits.hpp"
#include "holo/core/mesh.hpp"

namespace holo {

// Loads `.gltf` or `.glb` (chosen by extension).
Model loadGltf(const std::filesystem::path& path);
// Loads a binary glTF held in memory; `origin` stands in for the file name in errors.
Model loadGlbFromMemory(const std::vector<std::uint8_t>& glb, const std::string& origin);

// What a file asks of a viewer and how far this build honours it, for `holopyramid info`.
enum class GltfSupport {
  Rendered,  // loaded, and the renderers use it
  Ignored,   // an optional extension this build does not read
};
const char* describe(GltfSupport support);

struct GltfFeature {
  std::string name;  // an extension, a texture slot ("normalTexture") or a property
  GltfSupport support = GltfSupport::Ignored;
  bool required = false;  // in extensionsRequired
  int materials = 0;      // materials that use it (texture slots and properties)
};

struct GltfInventory {
  Model model;
  std::vector<GltfFeature> extensions;     // extensionsUsed and extensionsRequired, in file order
  std::vector<GltfFeature> texture_slots;  // material texture slots with at least one user
  std::vector<GltfFeature> properties;     // material properties beyond opaque factors, when used
};

// Loads the file as loadGltf does (same errors) and lists what it uses.
GltfInventory inspectGltf(const std::filesystem::path& path);

// Writes `.glb` or `.gltf` (buffers and images embedded, so one file) atomically: a crash never
// leaves half a model. Textures are stored as PNG. Emission above 1 uses
// KHR_materials_emissive_strength.
void saveGltf(const std::filesystem::path& path, const Model& model);
// The same model as binary glTF bytes.
std::vector<std::uint8_t> encodeGlb(const Model& model);

}  // namespace holo
