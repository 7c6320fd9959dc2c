// glTF materials into holo::Material (internal to core): every glTF 2.0 core property and the
// extensions named in gltf_io.hpp, each factor and texture reference checked. Factors must be
// finite and >= 0 (those glTF bounds by 1 are clamped there, counted in "glTF/Material factors
// clamped to 1"), a texCoord 0 or 1, an attenuationDistance > 0 and an IOR >= 1; InputError
// naming the material and the field otherwise.
#pragma once

#include <string>
#include <vector>

#include "gltf_textures.hpp"
#include "gltf_tinygltf.hpp"
#include "holo/core/mesh.hpp"

namespace holo::gltf_detail {

// True for the extensions whose every property readMaterials reads into holo::Material.
bool readsExtension(const std::string& name);

// Every material of `gltf` in file order; the textures they use are built through `textures`.
std::vector<Material> readMaterials(const tinygltf::Model& gltf, const std::string& file,
                                    TextureTable& textures);

}  // namespace holo::gltf_detail
