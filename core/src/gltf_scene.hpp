// A parsed glTF flattened into a holo::Model (internal to core), as gltf_io.hpp describes for
// loadGltf: the default scene's node hierarchy (or, without scenes, every mesh), each primitive
// one TriangleMesh, normals and tangents sanitised or generated, materials and textures read,
// the scene limits enforced.
#pragma once

#include <string>
#include <vector>

#include "gltf_tinygltf.hpp"
#include "holo/core/mesh.hpp"

namespace holo::gltf_detail {

// Where a loaded TriangleMesh came from, for the skinned loader (which keeps meshes in their own
// space and poses them itself).
struct MeshSource {
  int node = -1;  // -1: a file without scenes
  int mesh = -1;
  int primitive = -1;
};

// The rest transform of a node: its `matrix`, or T * R * S from its translation, rotation and
// scale (each identity when absent).
mat4 nodeMatrix(const tinygltf::Node& node);

// The model of `gltf`; `file` names it in errors. With `sources`, meshes stay in their own space
// (node transforms not applied) and their origins are listed in mesh order.
Model flattenScene(const tinygltf::Model& gltf, const std::string& file,
                   std::vector<MeshSource>* sources = nullptr);

}  // namespace holo::gltf_detail
