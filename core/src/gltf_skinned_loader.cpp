// loadSkinnedGltf (skinned_mesh.hpp): the skeleton, skins, skinned meshes and animation clips of
// a glTF. The meshes come from flattenScene in their own space, so they share loadGltf's
// checks, materials and textures; this file adds the invariants skinned_mesh.hpp lists.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "gltf_accessors.hpp"
#include "gltf_parse.hpp"
#include "gltf_scene.hpp"
#include "holo/core/log.hpp"
#include "holo/core/skinned_mesh.hpp"
#include "holo/core/stats.hpp"

namespace holo {

namespace fs = std::filesystem;

namespace {

using gltf_detail::AccessorReader;

// Every node's name and rest transform (finite), and its parent: children must form a forest.
void readNodes(const tinygltf::Model& gltf, const AccessorReader& reader, Skeleton& skeleton) {
  const int node_count = static_cast<int>(gltf.nodes.size());
  skeleton.nodes.resize(gltf.nodes.size());
  for (int i = 0; i < node_count; ++i) {
    const auto& node = gltf.nodes[static_cast<std::size_t>(i)];
    SkeletonNode& n = skeleton.nodes[static_cast<std::size_t>(i)];
    n.name = node.name;
    const std::string field = "nodes[" + std::to_string(i) + "]";
    if (node.matrix.size() == 16) {
      n.matrix = gltf_detail::nodeMatrix(node);
      for (int k = 0; k < 16; ++k)
        if (!std::isfinite(glm::value_ptr(n.matrix)[k])) reader.fail(field + ".matrix", "finite numbers");
    }
    if (node.translation.size() == 3)
      n.translation = vec3(static_cast<float>(node.translation[0]), static_cast<float>(node.translation[1]),
                           static_cast<float>(node.translation[2]));
    if (node.rotation.size() == 4)
      n.rotation = glm::quat(static_cast<float>(node.rotation[3]), static_cast<float>(node.rotation[0]),
                             static_cast<float>(node.rotation[1]), static_cast<float>(node.rotation[2]));
    if (node.scale.size() == 3)
      n.scale = vec3(static_cast<float>(node.scale[0]), static_cast<float>(node.scale[1]),
                     static_cast<float>(node.scale[2]));
    if (!isFinite(n.translation) || !isFinite(n.scale) ||
        !isFinite(vec4(n.rotation.x, n.rotation.y, n.rotation.z, n.rotation.w)))
      reader.fail(field, "a finite translation, rotation and scale");
    for (int child : node.children) {
      if (child < 0 || child >= node_count)
        reader.fail(field + ".children", "node indices < " + std::to_string(node_count),
                    std::to_string(child));
      SkeletonNode& c = skeleton.nodes[static_cast<std::size_t>(child)];
      if (c.parent >= 0 || child == i)
        reader.fail(field + ".children", "a tree (every node has at most one parent)",
                    "node " + std::to_string(child) + " has two");
      c.parent = i;
    }
  }
}

// Skeleton::order: each root, in node order, followed depth first by its subtree.
void orderNodes(const AccessorReader& reader, Skeleton& skeleton) {
  const int node_count = static_cast<int>(skeleton.nodes.size());
  std::vector<std::vector<int>> children(skeleton.nodes.size());
  for (int i = 0; i < node_count; ++i)
    if (const int parent = skeleton.nodes[static_cast<std::size_t>(i)].parent; parent >= 0)
      children[static_cast<std::size_t>(parent)].push_back(i);
  for (int i = 0; i < node_count; ++i) {
    if (skeleton.nodes[static_cast<std::size_t>(i)].parent >= 0) continue;
    std::vector<int> stack{i};
    while (!stack.empty()) {
      const int n = stack.back();
      stack.pop_back();
      skeleton.order.push_back(n);
      for (int c : children[static_cast<std::size_t>(n)]) stack.push_back(c);
    }
  }
  // A cycle has no root, so its nodes never reach `order`.
  if (skeleton.order.size() != skeleton.nodes.size())
    reader.fail("nodes", "an acyclic node hierarchy", "a cycle of children");
}

// Skin `s`: its joints (node indices) and one inverse bind matrix per joint (identity when the
// file gives none).
Skin readSkin(const tinygltf::Model& gltf, std::size_t s, const AccessorReader& reader) {
  const int node_count = static_cast<int>(gltf.nodes.size());
  const auto& gskin = gltf.skins[s];
  const std::string field = "skins[" + std::to_string(s) + "]";
  Skin skin;
  skin.name = gskin.name;
  if (gskin.joints.empty()) reader.fail(field + ".joints", "at least one joint", "none");
  for (int j : gskin.joints) {
    if (j < 0 || j >= node_count)
      reader.fail(field + ".joints", "node indices < " + std::to_string(node_count), std::to_string(j));
    skin.joints.push_back(j);
  }
  skin.inverse_bind.assign(skin.joints.size(), mat4(1.0f));
  if (gskin.inverseBindMatrices >= 0) {
    const std::string ibm_field = field + ".inverseBindMatrices";
    const std::vector<float> m = reader.readFloats(gskin.inverseBindMatrices, ibm_field, 16, "MAT4");
    if (m.size() / 16 < skin.joints.size())
      reader.fail(ibm_field, "one matrix per joint (" + std::to_string(skin.joints.size()) + ")",
                  std::to_string(m.size() / 16));
    for (std::size_t j = 0; j < skin.joints.size(); ++j)
      std::memcpy(glm::value_ptr(skin.inverse_bind[j]), m.data() + 16 * j, 16 * sizeof(float));
  }
  return skin;
}

// The joints and weights of `sm` from JOINTS_0 and WEIGHTS_0 (`field`: the primitive's
// attributes): one per position, weights >= 0 summing to 1 within 0.01, renormalised to exactly 1;
// a joint with weight > 0 must be one of the skin's `joint_count`.
void readInfluences(const AccessorReader& reader, int joints_accessor, int weights_accessor,
                    const std::string& field, std::size_t joint_count, SkinnedMesh& sm) {
  const std::size_t n = sm.mesh.positions.size();
  sm.joints = reader.readJoints(joints_accessor, field + ".JOINTS_0");
  const std::vector<float> w = reader.readFloats(weights_accessor, field + ".WEIGHTS_0", 4, "VEC4");
  if (sm.joints.size() != n) reader.fail(field + ".JOINTS_0", "one entry per position");
  if (w.size() != 4 * n) reader.fail(field + ".WEIGHTS_0", "one entry per position");
  sm.weights.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    vec4 wv(w[4 * v], w[4 * v + 1], w[4 * v + 2], w[4 * v + 3]);
    for (int k = 0; k < 4; ++k) {
      if (wv[k] < 0.0f)
        reader.fail(field + ".WEIGHTS_0", "weights >= 0",
                    std::to_string(wv[k]) + " at vertex " + std::to_string(v));
      if (wv[k] > 0.0f && sm.joints[v][k] >= joint_count)
        reader.fail(field + ".JOINTS_0",
                    "joint indices < the skin's " + std::to_string(joint_count) + " joints",
                    std::to_string(sm.joints[v][k]) + " at vertex " + std::to_string(v));
    }
    const float sum = wv.x + wv.y + wv.z + wv.w;
    if (std::abs(sum - 1.0f) > 0.01f)
      reader.fail(field + ".WEIGHTS_0", "weights summing to 1 (within 0.01)",
                  std::to_string(sum) + " at vertex " + std::to_string(v));
    sm.weights[v] = wv / sum;
  }
}

// A loaded mesh with its node and, when that node has a skin, the skin and its influences.
SkinnedMesh skinnedMesh(const tinygltf::Model& gltf, const AccessorReader& reader, const Skeleton& skeleton,
                        TriangleMesh mesh, const gltf_detail::MeshSource& src) {
  SkinnedMesh sm;
  sm.mesh = std::move(mesh);
  sm.node = src.node;
  const int skin = src.node >= 0 ? gltf.nodes[static_cast<std::size_t>(src.node)].skin : -1;
  const auto& prim =
      gltf.meshes[static_cast<std::size_t>(src.mesh)].primitives[static_cast<std::size_t>(src.primitive)];
  const std::string field =
      "meshes[" + std::to_string(src.mesh) + "].primitives[" + std::to_string(src.primitive) + "].attributes";
  const auto joints_it = prim.attributes.find("JOINTS_0");
  const auto weights_it = prim.attributes.find("WEIGHTS_0");
  if (skin >= static_cast<int>(skeleton.skins.size()))
    reader.fail("nodes[" + std::to_string(src.node) + "].skin",
                "a skin index < " + std::to_string(skeleton.skins.size()), std::to_string(skin));
  if (skin >= 0 && joints_it != prim.attributes.end() && weights_it != prim.attributes.end()) {
    sm.skin = skin;
    readInfluences(reader, joints_it->second, weights_it->second, field,
                   skeleton.skins[static_cast<std::size_t>(skin)].joints.size(), sm);
  } else if (skin >= 0) {
    reader.fail(field, "JOINTS_0 and WEIGHTS_0 on a primitive of a skinned node", "missing");
  }
  return sm;
}

// Channel `ch` of animation `a` (`field` names it) with its sampler's keys: times finite and
// non-decreasing, values finite, one (three for CUBICSPLINE) per key.
AnimationChannel readChannel(const tinygltf::Model& gltf, std::size_t a, const tinygltf::AnimationChannel& ch,
                             const std::string& field, const AccessorReader& reader) {
  const int node_count = static_cast<int>(gltf.nodes.size());
  const auto& anim = gltf.animations[a];
  AnimationChannel out_channel;
  if (ch.target_path == "translation") {
    out_channel.path = AnimationPath::translation;
  } else if (ch.target_path == "rotation") {
    out_channel.path = AnimationPath::rotation;
  } else if (ch.target_path == "scale") {
    out_channel.path = AnimationPath::scale;
  } else {
    reader.fail(field + ".target.path", "translation, rotation, scale or weights", ch.target_path);
  }
  if (ch.target_node < 0 || ch.target_node >= node_count)
    reader.fail(field + ".target.node", "a node index < " + std::to_string(node_count),
                std::to_string(ch.target_node));
  out_channel.node = ch.target_node;
  if (ch.sampler < 0 || ch.sampler >= static_cast<int>(anim.samplers.size()))
    reader.fail(field + ".sampler", "a sampler index < " + std::to_string(anim.samplers.size()),
                std::to_string(ch.sampler));
  const auto& sampler = anim.samplers[static_cast<std::size_t>(ch.sampler)];
  const std::string sfield =
      "animations[" + std::to_string(a) + "].samplers[" + std::to_string(ch.sampler) + "]";
  if (sampler.interpolation == "LINEAR" || sampler.interpolation.empty()) {
    out_channel.interpolation = Interpolation::linear;
  } else if (sampler.interpolation == "STEP") {
    out_channel.interpolation = Interpolation::step;
  } else if (sampler.interpolation == "CUBICSPLINE") {
    out_channel.interpolation = Interpolation::cubic_spline;
  } else {
    reader.fail(sfield + ".interpolation", "LINEAR, STEP or CUBICSPLINE", sampler.interpolation);
  }
  out_channel.times = reader.readFloats(sampler.input, sfield + ".input", 1, "SCALAR");
  if (out_channel.times.empty()) reader.fail(sfield + ".input", "at least one key time", "none");
  for (std::size_t k = 1; k < out_channel.times.size(); ++k)
    if (out_channel.times[k] < out_channel.times[k - 1])
      reader.fail(
          sfield + ".input", "non-decreasing key times",
          std::to_string(out_channel.times[k]) + " after " + std::to_string(out_channel.times[k - 1]));
  const bool rotation = out_channel.path == AnimationPath::rotation;
  const int components = rotation ? 4 : 3;
  const std::vector<float> values =
      reader.readFloats(sampler.output, sfield + ".output", components, rotation ? "VEC4" : "VEC3");
  const std::size_t per_key = out_channel.interpolation == Interpolation::cubic_spline ? 3 : 1;
  const std::size_t count = values.size() / static_cast<std::size_t>(components);
  if (count != per_key * out_channel.times.size())
    reader.fail(sfield + ".output",
                std::to_string(per_key) + " value(s) per key time (" +
                    std::to_string(per_key * out_channel.times.size()) + ")",
                std::to_string(count));
  for (std::size_t k = 0; k < count; ++k) {
    const float* v = values.data() + k * static_cast<std::size_t>(components);
    out_channel.values.emplace_back(v[0], v[1], v[2], rotation ? v[3] : 0.0f);
  }
  return out_channel;
}

// Animation `a` as a clip; channels that drive morph target weights are skipped (warned, counted).
AnimationClip readClip(const tinygltf::Model& gltf, std::size_t a, const AccessorReader& reader) {
  const auto& anim = gltf.animations[a];
  AnimationClip clip;
  clip.name = anim.name.empty() ? "animation" + std::to_string(a) : anim.name;
  for (std::size_t c = 0; c < anim.channels.size(); ++c) {
    const auto& ch = anim.channels[c];
    const std::string field = "animations[" + std::to_string(a) + "].channels[" + std::to_string(c) + "]";
    if (ch.target_path == "weights") {  // morph targets: this build has none to drive
      stats::add("glTF/Morph target animations ignored");
      HOLO_LOG_WARN("{}: {} animates morph target weights: ignored (not read)", reader.file(), field);
      continue;
    }
    AnimationChannel channel = readChannel(gltf, a, ch, field, reader);
    clip.duration = std::max(clip.duration, channel.times.back());
    clip.channels.push_back(std::move(channel));
  }
  return clip;
}

}  // namespace

SkinnedModel loadSkinnedGltf(const fs::path& path) {
  const tinygltf::Model gltf = gltf_detail::parseGltfFile(path);
  const std::string file = path.string();
  const AccessorReader reader(gltf, file);
  std::vector<gltf_detail::MeshSource> sources;
  Model flat = gltf_detail::flattenScene(gltf, file, &sources);
  SkinnedModel out;
  out.materials = std::move(flat.materials);
  out.textures = std::move(flat.textures);
  readNodes(gltf, reader, out.skeleton);
  orderNodes(reader, out.skeleton);
  for (std::size_t s = 0; s < gltf.skins.size(); ++s) out.skeleton.skins.push_back(readSkin(gltf, s, reader));
  for (std::size_t i = 0; i < flat.meshes.size(); ++i)
    out.meshes.push_back(skinnedMesh(gltf, reader, out.skeleton, std::move(flat.meshes[i]), sources[i]));
  for (std::size_t a = 0; a < gltf.animations.size(); ++a) out.clips.push_back(readClip(gltf, a, reader));
  return out;
}

}  // namespace holo
