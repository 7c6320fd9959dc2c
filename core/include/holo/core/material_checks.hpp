// What a model's materials do that its author may not expect, for `holopyramid info`: a
// material that makes its meshes invisible (alphaMode BLEND with baseColorFactor alpha 0: every
// texel's alpha is multiplied by 0), and a glass material whose KHR_materials_volume thickness is
// far from the size of the meshes that use it. The renderers trace the meshes' own walls (the
// thickness only tells a volume from a thin wall), while a rasterising viewer such as the Khronos
// glTF Sample Viewer refracts by the thickness: a factor far from the mesh's size makes the two
// pictures differ.
#pragma once

#include <string>
#include <vector>

#include "holo/core/mesh.hpp"

namespace holo {

// A thickness is "far" from the mesh's size when it is more than kThicknessFar times the meshes'
// median wall (the distance from a face inwards along its normal to the next face, over up to 256
// faces; model units, metres in glTF) or less than that wall / kThicknessFar.
inline constexpr float kThicknessFar = 10.0f;

struct MaterialWarning {
  std::size_t material = 0;  // index into Model::materials
  std::string message;       // one line, names the material and what to expect
};

// In material order; empty when nothing is surprising.
std::vector<MaterialWarning> checkMaterials(const Model& model);

}  // namespace holo
