#include "holo/core/skinned_mesh.hpp"

#include <algorithm>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <stdexcept>

namespace holo {

namespace {

vec4 hermite(const vec4& p0, const vec4& m0, const vec4& p1, const vec4& m1, float s, float dt) {
  const float s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * dt * m0 + (-2 * s3 + 3 * s2) * p1 +
         (s3 - s2) * dt * m1;
}

glm::quat toQuat(const vec4& v) {
  return glm::quat(v.w, v.x, v.y, v.z);
}

mat4 localMatrix(const SkeletonNode& n) {
  return n.matrix * glm::translate(mat4(1.0f), n.translation) * glm::mat4_cast(n.rotation) *
         glm::scale(mat4(1.0f), n.scale);
}

}  // namespace

vec4 sampleChannel(const AnimationChannel& c, float t) {
  const std::size_t keys = c.times.size();
  const bool cubic = c.interpolation == Interpolation::cubic_spline;
  const auto value = [&](std::size_t k) { return cubic ? c.values[3 * k + 1] : c.values[k]; };
  if (keys == 0) return vec4(0.0f);
  if (keys == 1 || t <= c.times.front()) return value(0);
  if (t >= c.times.back()) return value(keys - 1);
  const std::size_t k1 =
      static_cast<std::size_t>(std::upper_bound(c.times.begin(), c.times.end(), t) - c.times.begin());
  const std::size_t k0 = k1 - 1;
  const float dt = c.times[k1] - c.times[k0];
  const float s = dt > 0.0f ? (t - c.times[k0]) / dt : 0.0f;
  vec4 out;
  switch (c.interpolation) {
    case Interpolation::step:
      return value(k0);
    case Interpolation::linear:
      if (c.path == AnimationPath::rotation) {
        const glm::quat q = glm::slerp(toQuat(value(k0)), toQuat(value(k1)), s);  // shortest arc
        return vec4(q.x, q.y, q.z, q.w);
      }
      return glm::mix(value(k0), value(k1), s);
    case Interpolation::cubic_spline:
      out =
          hermite(c.values[3 * k0 + 1], c.values[3 * k0 + 2], c.values[3 * k1 + 1], c.values[3 * k1], s, dt);
      if (c.path == AnimationPath::rotation) {
        const float len = glm::length(out);
        if (len > 0.0f) out /= len;
      }
      return out;
  }
  return value(k0);
}

std::vector<mat4> nodeTransforms(const SkinnedModel& model, int clip, float t) {
  std::vector<SkeletonNode> nodes = model.skeleton.nodes;
  if (clip >= 0) {
    for (const AnimationChannel& c : model.clips.at(static_cast<std::size_t>(clip)).channels) {
      SkeletonNode& n = nodes.at(static_cast<std::size_t>(c.node));
      const vec4 v = sampleChannel(c, t);
      switch (c.path) {
        case AnimationPath::translation:
          n.translation = vec3(v);
          break;
        case AnimationPath::rotation:
          n.rotation = glm::normalize(toQuat(v));
          break;
        case AnimationPath::scale:
          n.scale = vec3(v);
          break;
      }
    }
  }
  std::vector<mat4> global(nodes.size(), mat4(1.0f));
  for (int i : model.skeleton.order) {
    const auto index = static_cast<std::size_t>(i);
    const mat4 local = localMatrix(nodes[index]);
    const int parent = nodes[index].parent;
    global[index] = parent < 0 ? local : global[static_cast<std::size_t>(parent)] * local;
  }
  return global;
}

Model poseSkinned(const SkinnedModel& model, int clip, float t) {
  const std::vector<mat4> global = nodeTransforms(model, clip, t);
  std::vector<std::vector<mat4>> joint_matrices;
  for (const Skin& skin : model.skeleton.skins) {
    std::vector<mat4> m(skin.joints.size());
    for (std::size_t j = 0; j < skin.joints.size(); ++j)
      m[j] = global[static_cast<std::size_t>(skin.joints[j])] * skin.inverse_bind[j];
    joint_matrices.push_back(std::move(m));
  }
  Model out;
  out.materials = model.materials;
  out.textures = model.textures;
  for (const SkinnedMesh& sm : model.meshes) {
    TriangleMesh mesh = sm.mesh;
    if (sm.skin < 0) {
      if (sm.node >= 0) mesh.transform(global[static_cast<std::size_t>(sm.node)]);
      out.meshes.push_back(std::move(mesh));
      continue;
    }
    const std::vector<mat4>& J = joint_matrices[static_cast<std::size_t>(sm.skin)];
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      mat4 blended(0.0f);
      for (int k = 0; k < 4; ++k)
        if (sm.weights[v][k] > 0.0f) blended += sm.weights[v][k] * J[sm.joints[v][k]];
      mesh.positions[v] = vec3(blended * vec4(mesh.positions[v], 1.0f));
      const mat3 linear(blended);
      if (!mesh.normals.empty()) {
        const vec3 n = glm::inverseTranspose(linear) * mesh.normals[v];
        const float len = glm::length(n);
        mesh.normals[v] = len > 0.0f ? n / len : vec3(0, 1, 0);
      }
      if (!mesh.tangents.empty()) {
        const vec3 tg = linear * vec3(mesh.tangents[v]);
        const float len = glm::length(tg);
        if (len > 0.0f) mesh.tangents[v] = vec4(tg / len, mesh.tangents[v].w);
      }
    }
    out.meshes.push_back(std::move(mesh));
  }
  return out;
}

}  // namespace holo
