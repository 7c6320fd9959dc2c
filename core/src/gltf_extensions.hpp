// The names of the glTF extensions the reader and the writer handle (internal to core).
#pragma once

namespace holo::gltf_detail {

inline constexpr const char* kDraco = "KHR_draco_mesh_compression";
inline constexpr const char* kEmissiveStrength = "KHR_materials_emissive_strength";
inline constexpr const char* kTextureTransform = "KHR_texture_transform";
inline constexpr const char* kSpecular = "KHR_materials_specular";
inline constexpr const char* kClearcoat = "KHR_materials_clearcoat";
inline constexpr const char* kTransmission = "KHR_materials_transmission";
inline constexpr const char* kVolume = "KHR_materials_volume";
inline constexpr const char* kIor = "KHR_materials_ior";

}  // namespace holo::gltf_detail
