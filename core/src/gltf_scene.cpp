#include "gltf_scene.hpp"

#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "gltf_accessors.hpp"
#include "gltf_extensions.hpp"
#include "gltf_materials.hpp"
#include "gltf_textures.hpp"
#include "holo/core/error.hpp"
#include "holo/core/gltf_limits.hpp"
#include "holo/core/log.hpp"
#include "holo/core/stats.hpp"

namespace holo::gltf_detail {

namespace {

std::vector<uvec3> trianglesFromIndices(const std::vector<std::uint32_t>& idx, int mode,
                                        const AccessorReader& r, const std::string& field) {
  std::vector<uvec3> tris;
  switch (mode) {
    case TINYGLTF_MODE_TRIANGLES:
      if (idx.size() % 3 != 0)
        r.fail(field, "a multiple of 3 indices for TRIANGLES", std::to_string(idx.size()));
      for (std::size_t i = 0; i + 2 < idx.size(); i += 3) tris.emplace_back(idx[i], idx[i + 1], idx[i + 2]);
      break;
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      for (std::size_t i = 0; i + 2 < idx.size(); ++i)
        tris.push_back(i % 2 == 0 ? uvec3(idx[i], idx[i + 1], idx[i + 2])
                                  : uvec3(idx[i + 1], idx[i], idx[i + 2]));
      break;
    case TINYGLTF_MODE_TRIANGLE_FAN:
      for (std::size_t i = 1; i + 1 < idx.size(); ++i) tris.emplace_back(idx[0], idx[i], idx[i + 1]);
      break;
    default:
      break;
  }
  return tris;
}

// Refuses a required extension this build does not read (Draco by name); an optional one is
// skipped with one warning per file and counted.
void checkExtensions(const tinygltf::Model& gltf, const std::string& file) {
  for (const auto& ext : gltf.extensionsRequired) {
    if (ext == kDraco)
      throw InputError(file, "extensionsRequired",
                       "meshes without Draco compression (this build has no Draco decoder; re-export "
                       "the model without compression)",
                       kDraco);
    if (!readsExtension(ext))
      throw InputError(file, "extensionsRequired", "only extensions this build reads", ext);
  }
  std::string ignored;
  for (const auto& ext : gltf.extensionsUsed) {
    if (readsExtension(ext) || ext == kDraco) continue;
    stats::add("glTF/Optional extensions ignored");
    ignored += (ignored.empty() ? "" : ", ") + ext;
  }
  if (!ignored.empty()) HOLO_LOG_WARN("{}: optional extensions ignored (not read): {}", file, ignored);
}

// Normalises the mesh's normals. False when it has none or one is zero or not finite (such a
// normal would poison shading), leaving them for the caller to recompute, all of them.
bool normaliseNormals(TriangleMesh& mesh) {
  bool normals_ok = !mesh.normals.empty();
  for (auto& nrm : mesh.normals) {
    const float len = glm::length(nrm);
    if (!std::isfinite(len) || len < 1e-6f) {
      normals_ok = false;
      break;
    }
    nrm /= len;
  }
  return normals_ok;
}

// Walks the node hierarchy and appends every primitive it instances to a Model whose materials
// are already read; counts the instances against the scene limits.
class SceneFlattener {
 public:
  SceneFlattener(const tinygltf::Model& gltf, const std::string& file, Model& model,
                 std::vector<MeshSource>* sources)
      : gltf_(gltf),
        file_(file),
        reader_(gltf, file),
        model_(model),
        sources_(sources),
        default_material_(static_cast<int>(model.materials.size())) {}

  // Node `node_index` and its subtree, under a parent whose global transform is `parent`.
  void visit(int node_index, const mat4& parent, int depth) {
    if (node_index < 0 || node_index >= static_cast<int>(gltf_.nodes.size()))
      reader_.fail("nodes", "a node index < " + std::to_string(gltf_.nodes.size()),
                   std::to_string(node_index));
    if (depth > 256) reader_.fail("nodes", "an acyclic node hierarchy", "depth > 256");
    // Nodes shared between parents multiply: a few hundred can stand for billions of visits.
    if (++node_visits_ > kMaxGltfNodeVisits)
      reader_.fail("nodes", "at most " + std::to_string(kMaxGltfNodeVisits) + " node instances in the scene",
                   "more (nodes shared by many parents)");
    const auto& node = gltf_.nodes[static_cast<std::size_t>(node_index)];
    const mat4 T = parent * nodeMatrix(node);
    if (node.mesh >= 0) addMesh(node.mesh, T, node_index);
    for (int child : node.children) visit(child, T, depth + 1);
  }

  // Every primitive of mesh `mesh_index` as instanced by node `node_index` (-1: none) with global
  // transform `T`.
  void addMesh(int mesh_index, const mat4& T, int node_index) {
    if (mesh_index < 0 || mesh_index >= static_cast<int>(gltf_.meshes.size()))
      reader_.fail("nodes[].mesh", "a mesh index < " + std::to_string(gltf_.meshes.size()),
                   std::to_string(mesh_index));
    const auto& mesh = gltf_.meshes[static_cast<std::size_t>(mesh_index)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const auto& prim = mesh.primitives[p];
      const std::string field =
          "meshes[" + std::to_string(mesh_index) + "].primitives[" + std::to_string(p) + "]";
      TriangleMesh out = readGeometry(prim, field);
      out.name = mesh.name.empty() ? "mesh" + std::to_string(mesh_index) : mesh.name;
      if (mesh.primitives.size() > 1) out.name += "." + std::to_string(p);
      countInstance(out, field);
      const bool normals_ok = normaliseNormals(out);
      if (!normals_ok) out.computeNormals();
      const TextureRef* normal_map = assignMaterial(out, prim.material);
      settleTangents(out, normals_ok, normal_map, field);
      if (sources_) {
        sources_->push_back({node_index, mesh_index, static_cast<int>(p)});
      } else {
        out.transform(T);
      }
      model_.meshes.push_back(std::move(out));
    }
  }

  // True once a primitive without a valid material was given the default one (index: the
  // number of materials read), which the caller then appends.
  bool usedDefaultMaterial() const { return used_default_; }

 private:
  // Positions, the optional attributes and the triangles of one primitive, in its own space.
  TriangleMesh readGeometry(const tinygltf::Primitive& prim, const std::string& field) const {
    if (prim.extensions.count(kDraco))
      reader_.fail(field + ".extensions", "an uncompressed primitive (no Draco decoder in this build)",
                   kDraco);
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        prim.mode != TINYGLTF_MODE_TRIANGLE_FAN && prim.mode != -1)
      reader_.fail(field + ".mode", "triangles (mode 4, 5 or 6)",
                   "mode " + std::to_string(prim.mode) + (prim.mode <= 3 ? " (points or lines)" : ""));
    const auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) reader_.fail(field + ".attributes", "a POSITION attribute", "none");
    TriangleMesh out;
    out.positions = reader_.readVec<3>(pos_it->second, field + ".attributes.POSITION");
    const std::size_t n = out.positions.size();
    for (std::size_t i = 0; i < n; ++i)
      if (!isFinite(out.positions[i]))
        reader_.fail(field + ".attributes.POSITION", "finite positions",
                     "NaN or Inf at vertex " + std::to_string(i));
    out.normals = attribute<3>(prim, "NORMAL", field, n, "one normal per position");
    out.uvs = attribute<2>(prim, "TEXCOORD_0", field, n, "one uv per position");
    out.uvs1 = attribute<2>(prim, "TEXCOORD_1", field, n, "one uv per position");
    out.tangents = attribute<4>(prim, "TANGENT", field, n, "one tangent per position");
    const std::vector<std::uint32_t> idx = indices(prim, field, n);
    out.triangles = trianglesFromIndices(idx, prim.mode == -1 ? TINYGLTF_MODE_TRIANGLES : prim.mode, reader_,
                                         field + ".indices");
    return out;
  }

  // Optional vertex attribute `name`: empty when absent, else one value per position (`n`).
  template <int N>
  std::vector<glm::vec<N, float>> attribute(const tinygltf::Primitive& prim, const char* name,
                                            const std::string& field, std::size_t n,
                                            const char* expected) const {
    const auto it = prim.attributes.find(name);
    if (it == prim.attributes.end()) return {};
    const std::string attribute_field = field + ".attributes." + name;
    std::vector<glm::vec<N, float>> values = reader_.readVec<N>(it->second, attribute_field);
    if (values.size() != n) reader_.fail(attribute_field, expected);
    return values;
  }

  // The primitive's indices, each < `n`; 0..n-1 when it has none.
  std::vector<std::uint32_t> indices(const tinygltf::Primitive& prim, const std::string& field,
                                     std::size_t n) const {
    std::vector<std::uint32_t> idx;
    if (prim.indices >= 0) {
      idx = reader_.readIndices(prim.indices, field + ".indices");
      for (std::size_t i = 0; i < idx.size(); ++i)
        if (idx[i] >= n)
          reader_.fail(field + ".indices", "indices < vertex count " + std::to_string(n),
                       "index " + std::to_string(idx[i]) + " at position " + std::to_string(i));
    } else {
      idx.resize(n);
      for (std::size_t i = 0; i < n; ++i) idx[i] = static_cast<std::uint32_t>(i);
    }
    return idx;
  }

  // Instances count: a node hierarchy can repeat one small mesh millions of times.
  void countInstance(const TriangleMesh& mesh, const std::string& field) {
    total_triangles_ += mesh.triangles.size();
    total_vertices_ += mesh.positions.size();
    if (total_triangles_ > kMaxGltfTriangles || total_vertices_ > kMaxGltfVertices)
      reader_.fail(field,
                   "a model of at most " + std::to_string(kMaxGltfTriangles) + " triangles and " +
                       std::to_string(kMaxGltfVertices) + " vertices, instances included (decimate it)",
                   std::to_string(total_triangles_) + " triangles and " + std::to_string(total_vertices_) +
                       " vertices so far");
  }

  // Gives the mesh material `material`, or the default one when that is not a valid index;
  // returns the normal map its tangents follow (the normal texture, else the clearcoat's), if any.
  const TextureRef* assignMaterial(TriangleMesh& mesh, int material) {
    if (material >= 0 && material < default_material_) {
      mesh.material = material;
    } else {
      mesh.material = default_material_;
      used_default_ = true;
    }
    const Material* mat = mesh.material < default_material_
                              ? &model_.materials[static_cast<std::size_t>(mesh.material)]
                              : nullptr;
    if (mat && mat->normal_texture.used()) return &mat->normal_texture;
    if (mat && mat->clearcoat_normal_texture.used()) return &mat->clearcoat_normal_texture;
    return nullptr;
  }

  // Tangents from the file are used when they are finite with unit xyz and w = +-1, and when the
  // normals they go with were kept; otherwise the glTF specification asks for MikkTSpace. Every
  // textured primitive gets a tangent frame, so a renderer never meets a material whose maps it
  // cannot orient.
  void settleTangents(TriangleMesh& out, bool normals_ok, const TextureRef* normal_map,
                      const std::string& field) const {
    bool tangents_ok = normals_ok && !out.tangents.empty();
    for (std::size_t i = 0; tangents_ok && i < out.tangents.size(); ++i) {
      const vec4& t = out.tangents[i];
      const vec3 in_plane = vec3(t) - out.normals[i] * glm::dot(out.normals[i], vec3(t));
      const float len = glm::length(in_plane);
      tangents_ok = std::isfinite(len) && len > 1e-6f && std::abs(std::abs(t.w) - 1.0f) < 1e-3f;
    }
    if (!out.tangents.empty() && !tangents_ok) {
      stats::add("glTF/Tangents regenerated");
      HOLO_LOG_WARN(
          "{}: {}.attributes.TANGENT unusable (non-finite, zero or with recomputed normals): "
          "regenerated",
          file_, field);
    }
    if (tangents_ok) {
      for (std::size_t i = 0; i < out.positions.size(); ++i) {
        const vec3 nv = out.normals[i];
        const vec3 t = vec3(out.tangents[i]) - nv * glm::dot(nv, vec3(out.tangents[i]));
        out.tangents[i] = vec4(glm::normalize(t), out.tangents[i].w < 0.0f ? -1.0f : 1.0f);
      }
    } else if (normal_map || !out.tangents.empty() || !out.uvs.empty()) {
      out.computeTangents(normal_map ? normal_map->tex_coord : 0);
    }
  }

  const tinygltf::Model& gltf_;
  const std::string& file_;
  const AccessorReader reader_;
  Model& model_;
  std::vector<MeshSource>* sources_;
  const int default_material_;
  bool used_default_ = false;
  std::size_t total_triangles_ = 0;
  std::size_t total_vertices_ = 0;
  std::size_t node_visits_ = 0;
};

}  // namespace

mat4 nodeMatrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) {
    mat4 m;
    for (int i = 0; i < 16; ++i)
      glm::value_ptr(m)[i] = static_cast<float>(node.matrix[static_cast<std::size_t>(i)]);
    return m;
  }
  mat4 T(1.0f);
  if (node.translation.size() == 3)
    T = glm::translate(mat4(1.0f),
                       vec3(static_cast<float>(node.translation[0]), static_cast<float>(node.translation[1]),
                            static_cast<float>(node.translation[2])));
  mat4 R(1.0f);
  if (node.rotation.size() == 4)  // glTF quaternion order x, y, z, w
    R = glm::mat4_cast(glm::quat(static_cast<float>(node.rotation[3]), static_cast<float>(node.rotation[0]),
                                 static_cast<float>(node.rotation[1]), static_cast<float>(node.rotation[2])));
  mat4 S(1.0f);
  if (node.scale.size() == 3)
    S = glm::scale(mat4(1.0f), vec3(static_cast<float>(node.scale[0]), static_cast<float>(node.scale[1]),
                                    static_cast<float>(node.scale[2])));
  return T * R * S;
}

Model flattenScene(const tinygltf::Model& gltf, const std::string& file, std::vector<MeshSource>* sources) {
  checkExtensions(gltf, file);
  Model model;
  TextureTable textures(gltf, file, model.textures);
  model.materials = readMaterials(gltf, file, textures);
  SceneFlattener flattener(gltf, file, model, sources);
  if (!gltf.scenes.empty()) {
    const int scene = gltf.defaultScene >= 0 && gltf.defaultScene < static_cast<int>(gltf.scenes.size())
                          ? gltf.defaultScene
                          : 0;
    for (int root : gltf.scenes[static_cast<std::size_t>(scene)].nodes) flattener.visit(root, mat4(1.0f), 0);
  } else {
    for (int i = 0; i < static_cast<int>(gltf.meshes.size()); ++i) flattener.addMesh(i, mat4(1.0f), -1);
  }
  if (flattener.usedDefaultMaterial()) {
    Material fallback;
    fallback.name = "default";
    model.materials.push_back(fallback);
  }
  if (model.meshes.empty()) throw InputError(file, "meshes", "at least one triangle mesh", "none");
  return model;
}

}  // namespace holo::gltf_detail
