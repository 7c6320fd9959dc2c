// Skinned, animated triangle meshes (glTF 2.0 skins and animations) and their posing by linear
// blend skinning into an ordinary holo::Model.
//
// A SkinnedModel keeps the glTF node hierarchy (Skeleton: every node, its parent and rest
// transform), the skins (joints as node indices, inverse bind matrices), every mesh primitive in
// its own mesh space with up to four joint influences per vertex, and the animation clips
// (translation, rotation and scale channels, LINEAR, STEP or CUBICSPLINE). poseSkinned(model,
// clip, t) samples the clip at t seconds, composes the node transforms and skins each vertex:
//   p' = sum_k w_k J[j_k] p,  J[j] = global(joint node j) * inverseBind[j]
// as glTF specifies (the skinned mesh node's own transform is ignored); normals and tangents go
// through the blended matrix's inverse transpose (normals) or itself (tangents) and are
// renormalised. A primitive on a node without a skin moves rigidly with its node.
// Units: whatever the file uses (glTF: metres), seconds.
//
// Invariants (checked by loadSkinnedGltf, InputError naming file and field otherwise): every
// joint index < its skin's joint count; weights finite, >= 0 and summing to 1 within 0.01 (then
// renormalised to exactly 1); inverse bind matrices and keyframe values finite; keyframe times
// finite and non-decreasing; a node's parent precedes nothing in particular, but the hierarchy
// is acyclic (Skeleton::order lists parents before children).
#pragma once

#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <vector>

#include "holo/core/mesh.hpp"

namespace holo {

struct SkeletonNode {
  std::string name;
  int parent = -1;    // index into Skeleton::nodes; -1 for a scene root
  mat4 matrix{1.0f};  // the node's `matrix` (identity when it has TRS instead)
  vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // w, x, y, z
  vec3 scale{1.0f};
};

struct Skin {
  std::string name;
  std::vector<int> joints;         // node indices
  std::vector<mat4> inverse_bind;  // one per joint
};

struct Skeleton {
  std::vector<SkeletonNode> nodes;
  std::vector<int> order;  // node indices, every parent before its children
  std::vector<Skin> skins;
};

struct SkinnedMesh {
  TriangleMesh mesh;               // bind pose, in the mesh node's own space (before any node transform)
  int node = -1;                   // the node that instances it
  int skin = -1;                   // index into Skeleton::skins; -1: rigid, moves with `node`
  std::vector<glm::uvec4> joints;  // per vertex: indices into the skin's joint list (skin >= 0)
  std::vector<vec4> weights;       // per vertex, summing to 1 (skin >= 0)
};

enum class AnimationPath { translation, rotation, scale };
enum class Interpolation { linear, step, cubic_spline };

struct AnimationChannel {
  int node = -1;
  AnimationPath path = AnimationPath::translation;
  Interpolation interpolation = Interpolation::linear;
  std::vector<float> times;  // seconds, non-decreasing
  std::vector<vec4> values;  // xyz (translation, scale) or quaternion xyzw (rotation); for
                             // cubic_spline three per key: in-tangent, value, out-tangent
};

struct AnimationClip {
  std::string name;
  std::vector<AnimationChannel> channels;
  float duration = 0.0f;  // seconds: the latest key time
};

struct SkinnedModel {
  Skeleton skeleton;
  std::vector<SkinnedMesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<AnimationClip> clips;
};

// Loads the skins, meshes and animations of a `.gltf`/`.glb` (same file limits and errors as
// loadGltf, plus the invariants above).
SkinnedModel loadSkinnedGltf(const std::filesystem::path& path);

// Global transform of every node with clip `clip` sampled at t seconds (clamped to the keys'
// range; clip -1: the rest pose, no animation). Throws std::out_of_range for a bad clip.
std::vector<mat4> nodeTransforms(const SkinnedModel& model, int clip, float t);

// The model posed at t seconds of clip `clip` (-1: rest pose) as ordinary triangle meshes,
// materials and textures copied.
Model poseSkinned(const SkinnedModel& model, int clip, float t);

// The value of one channel at t (clamped), as the glTF specification interpolates: lerp for
// translation and scale, slerp (shortest arc) for rotation, Hermite for cubic splines.
vec4 sampleChannel(const AnimationChannel& channel, float t);

}  // namespace holo
