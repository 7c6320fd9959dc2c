// glTF I/O through tinygltf. This is the one translation unit that compiles tinygltf's and
// stb_image_write's implementations (Debian ships them header-only for us; libstb.so is not
// linked). Reading textures goes through OpenCV, never stb_image (see decodeTexture).
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wcast-align"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb_image_write.h>
#include <tiny_gltf.h>
#pragma GCC diagnostic pop

#include "holo/core/gltf_io.hpp"

#include <algorithm>
#include <cstring>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/log.hpp"

namespace holo {

namespace fs = std::filesystem;

namespace {

constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kEmissiveStrength = "KHR_materials_emissive_strength";

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string firstLine(const std::string& s) {
  std::string out = s.substr(0, s.find('\n'));
  return out.empty() ? "unknown error" : out;
}

// Reads accessors, checking every offset against its buffer so a malformed file gives an
// InputError instead of reading out of bounds.
class Reader {
 public:
  Reader(const tinygltf::Model& gltf, std::string file) : gltf_(gltf), file_(std::move(file)) {}

  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const std::string& field, const std::string& expected,
                         const std::string& got = {}) const {
    throw InputError(file_, field, expected, got);
  }

  // Where an accessor's elements lie, checked against its buffer view and buffer before anything
  // is allocated for them: `count` comes from the file and may claim billions.
  struct Span {
    const unsigned char* base = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
  };

  Span span(int accessor_index, const std::string& field) const {
    if (accessor_index < 0 || accessor_index >= static_cast<int>(gltf_.accessors.size()))
      fail(field, "an accessor index < " + std::to_string(gltf_.accessors.size()),
           std::to_string(accessor_index));
    const auto& acc = gltf_.accessors[static_cast<std::size_t>(accessor_index)];
    const std::string acc_field = "accessors[" + std::to_string(accessor_index) + "]";
    if (acc.sparse.isSparse) fail(acc_field + ".sparse", "a dense accessor", "sparse");
    if (acc.bufferView < 0 || acc.bufferView >= static_cast<int>(gltf_.bufferViews.size()))
      fail(acc_field + ".bufferView", "a buffer view holding the data",
           "bufferView " + std::to_string(acc.bufferView));
    const auto& view = gltf_.bufferViews[static_cast<std::size_t>(acc.bufferView)];
    const std::string view_field = "bufferViews[" + std::to_string(acc.bufferView) + "]";
    if (view.buffer < 0 || view.buffer >= static_cast<int>(gltf_.buffers.size()))
      fail(view_field + ".buffer", "an existing buffer", "buffer " + std::to_string(view.buffer));
    const auto& buffer = gltf_.buffers[static_cast<std::size_t>(view.buffer)];
    const int element_size =
        tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(acc.componentType)) *
        tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type));
    if (element_size <= 0) fail(acc_field + ".componentType", "a valid component type and type");
    const int stride = acc.ByteStride(view);
    if (stride <= 0) fail(view_field + ".byteStride", "a stride of at least one element");
    if (acc.count == 0) return {};
    // Offsets and counts come from the file: compare them without overflow, against the view
    // clipped to the bytes the buffer really has.
    const std::size_t size = buffer.data.size();
    const std::size_t view_end =
        view.byteOffset > size ? 0 : view.byteOffset + std::min(view.byteLength, size - view.byteOffset);
    const std::size_t start = view.byteOffset + acc.byteOffset;
    const auto element = static_cast<std::size_t>(element_size);
    const bool inside = view.byteOffset <= size && acc.byteOffset <= size && start <= view_end &&
                        element <= view_end - start &&
                        acc.count - 1 <= (view_end - start - element) / static_cast<std::size_t>(stride);
    if (!inside)
      fail(acc_field,
           "data inside buffer " + std::to_string(view.buffer) + " (" + std::to_string(buffer.data.size()) +
               " bytes)",
           std::to_string(acc.count) + " elements of " + std::to_string(element_size) + " bytes from byte " +
               std::to_string(start) + " (missing or truncated buffer?)");
    return {buffer.data.data() + start, static_cast<std::size_t>(stride), acc.count};
  }

  // Calls `visit(i, const unsigned char* element)` for each element of the accessor.
  void forEach(const Span& s, const std::function<void(std::size_t, const unsigned char*)>& visit) const {
    for (std::size_t i = 0; i < s.count; ++i) visit(i, s.base + i * s.stride);
  }

  const tinygltf::Accessor& accessor(int index) const {
    return gltf_.accessors.at(static_cast<std::size_t>(index));
  }

  // A float vector attribute (normalized integers allowed for texture coordinates).
  template <int N>
  std::vector<glm::vec<N, float>> readVec(int accessor_index, const std::string& field) const {
    std::vector<glm::vec<N, float>> out;
    if (accessor_index < 0 || accessor_index >= static_cast<int>(gltf_.accessors.size()))
      fail(field, "an accessor index < " + std::to_string(gltf_.accessors.size()),
           std::to_string(accessor_index));
    const auto& acc = accessor(accessor_index);
    if (tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type)) != N)
      fail(field, "a VEC" + std::to_string(N) + " accessor");
    const int ct = acc.componentType;
    if (acc.count > kMaxGltfVertices)
      fail(field,
           "at most " + std::to_string(kMaxGltfVertices) + " vertices per primitive (decimate the model)",
           std::to_string(acc.count));
    const Span elements = span(accessor_index, field);
    out.resize(elements.count);
    forEach(elements, [&](std::size_t i, const unsigned char* p) {
      for (int k = 0; k < N; ++k) {
        float v = 0;
        switch (ct) {
          case TINYGLTF_COMPONENT_TYPE_FLOAT:
            std::memcpy(&v, p + 4 * k, 4);
            break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            v = p[k] / 255.0f;
            break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            std::uint16_t s;
            std::memcpy(&s, p + 2 * k, 2);
            v = s / 65535.0f;
            break;
          }
          default:
            fail(field, "FLOAT, UNSIGNED_BYTE or UNSIGNED_SHORT components",
                 "componentType " + std::to_string(ct));
        }
        out[i][k] = v;
      }
    });
    return out;
  }

  std::vector<std::uint32_t> readIndices(int accessor_index, const std::string& field) const {
    std::vector<std::uint32_t> out;
    if (accessor_index < 0 || accessor_index >= static_cast<int>(gltf_.accessors.size()))
      fail(field, "an accessor index < " + std::to_string(gltf_.accessors.size()),
           std::to_string(accessor_index));
    const auto& acc = accessor(accessor_index);
    if (acc.type != TINYGLTF_TYPE_SCALAR) fail(field, "a SCALAR index accessor");
    const int ct = acc.componentType;
    if (acc.count > 3 * kMaxGltfTriangles + 2)
      fail(field,
           "at most " + std::to_string(kMaxGltfTriangles) + " triangles (" +
               std::to_string(3 * kMaxGltfTriangles) + " indices; decimate the model)",
           std::to_string(acc.count) + " indices");
    const Span elements = span(accessor_index, field);
    out.resize(elements.count);
    forEach(elements, [&](std::size_t i, const unsigned char* p) {
      switch (ct) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          out[i] = p[0];
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          std::uint16_t s;
          std::memcpy(&s, p, 2);
          out[i] = s;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
          std::memcpy(&out[i], p, 4);
          break;
        default:
          fail(field, "unsigned byte, short or int indices", "componentType " + std::to_string(ct));
      }
    });
    return out;
  }

 private:
  const tinygltf::Model& gltf_;
  std::string file_;
};

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

std::vector<uvec3> trianglesFromIndices(const std::vector<std::uint32_t>& idx, int mode, const Reader& r,
                                        const std::string& field) {
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

cv::Mat decodeImage(const tinygltf::Image& image) {
  if (image.image.empty() || image.width <= 0 || image.height <= 0) return {};
  const int channels = image.component;
  if (channels < 1 || channels > 4) return {};
  cv::Mat raw;
  if (image.bits == 16) {
    cv::Mat wide(image.height, image.width, CV_16UC(channels),
                 const_cast<unsigned char*>(image.image.data()));
    wide.convertTo(raw, CV_8U, 1.0 / 257.0);
  } else {
    raw = cv::Mat(image.height, image.width, CV_8UC(channels), const_cast<unsigned char*>(image.image.data()))
              .clone();
  }
  cv::Mat out;
  switch (channels) {
    case 1:
      cv::cvtColor(raw, out, cv::COLOR_GRAY2BGR);
      break;
    case 2: {
      cv::Mat gray;
      cv::extractChannel(raw, gray, 0);
      cv::cvtColor(gray, out, cv::COLOR_GRAY2BGR);
      break;
    }
    case 3:
      cv::cvtColor(raw, out, cv::COLOR_RGB2BGR);
      break;
    default: {
      // An opaque texture drops its alpha.
      cv::Mat alpha;
      cv::extractChannel(raw, alpha, 3);
      double lowest = 0;
      cv::minMaxLoc(alpha, &lowest);
      cv::cvtColor(raw, out, lowest >= 255.0 ? cv::COLOR_RGBA2BGR : cv::COLOR_RGBA2BGRA);
      break;
    }
  }
  return out;
}

Model convert(const tinygltf::Model& gltf, const std::string& file) {
  for (const auto& ext : gltf.extensionsRequired)
    if (ext == kDraco)
      throw InputError(file, "extensionsRequired",
                       "meshes without Draco compression (this build has no Draco decoder; re-export "
                       "the model without compression)",
                       kDraco);
  const Reader reader(gltf, file);
  Model model;

  // Textures: glTF texture index -> Model::textures index (decoded once per texture).
  std::vector<int> texture_slot(gltf.textures.size(), -1);
  auto textureFor = [&](int gltf_texture) -> int {
    if (gltf_texture < 0 || gltf_texture >= static_cast<int>(gltf.textures.size())) return -1;
    auto& slot = texture_slot[static_cast<std::size_t>(gltf_texture)];
    if (slot >= 0) return slot;
    const int source = gltf.textures[static_cast<std::size_t>(gltf_texture)].source;
    if (source < 0 || source >= static_cast<int>(gltf.images.size())) return -1;
    cv::Mat decoded = decodeImage(gltf.images[static_cast<std::size_t>(source)]);
    if (decoded.empty()) {
      HOLO_LOG_WARN("{}: images[{}]: could not decode, texture ignored", file, source);
      return -1;
    }
    slot = static_cast<int>(model.textures.size());
    model.textures.push_back(std::move(decoded));
    return slot;
  };

  for (const auto& m : gltf.materials) {
    Material mat;
    mat.name = m.name;
    const auto& pbr = m.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() >= 3)
      mat.base_color =
          vec3(static_cast<float>(pbr.baseColorFactor[0]), static_cast<float>(pbr.baseColorFactor[1]),
               static_cast<float>(pbr.baseColorFactor[2]));
    mat.metallic = std::clamp(static_cast<float>(pbr.metallicFactor), 0.0f, 1.0f);
    mat.roughness = std::clamp(static_cast<float>(pbr.roughnessFactor), 0.0f, 1.0f);
    if (m.emissiveFactor.size() == 3) {
      float strength = 1.0f;
      if (auto it = m.extensions.find(kEmissiveStrength);
          it != m.extensions.end() && it->second.Has("emissiveStrength"))
        strength = static_cast<float>(it->second.Get("emissiveStrength").GetNumberAsDouble());
      mat.emission =
          strength * vec3(static_cast<float>(m.emissiveFactor[0]), static_cast<float>(m.emissiveFactor[1]),
                          static_cast<float>(m.emissiveFactor[2]));
    }
    mat.base_color_texture = textureFor(pbr.baseColorTexture.index);
    mat.metallic_roughness_texture = textureFor(pbr.metallicRoughnessTexture.index);
    model.materials.push_back(std::move(mat));
  }
  const int default_material = static_cast<int>(model.materials.size());
  bool used_default = false;
  std::size_t total_triangles = 0;
  std::size_t total_vertices = 0;

  auto addMesh = [&](int mesh_index, const mat4& T) {
    if (mesh_index < 0 || mesh_index >= static_cast<int>(gltf.meshes.size()))
      reader.fail("nodes[].mesh", "a mesh index < " + std::to_string(gltf.meshes.size()),
                  std::to_string(mesh_index));
    const auto& mesh = gltf.meshes[static_cast<std::size_t>(mesh_index)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const auto& prim = mesh.primitives[p];
      const std::string field =
          "meshes[" + std::to_string(mesh_index) + "].primitives[" + std::to_string(p) + "]";
      if (prim.extensions.count(kDraco))
        reader.fail(field + ".extensions", "an uncompressed primitive (no Draco decoder in this build)",
                    kDraco);
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          prim.mode != TINYGLTF_MODE_TRIANGLE_FAN && prim.mode != -1)
        reader.fail(field + ".mode", "triangles (mode 4, 5 or 6)",
                    "mode " + std::to_string(prim.mode) + (prim.mode <= 3 ? " (points or lines)" : ""));
      const auto pos_it = prim.attributes.find("POSITION");
      if (pos_it == prim.attributes.end()) reader.fail(field + ".attributes", "a POSITION attribute", "none");
      TriangleMesh out;
      out.name = mesh.name.empty() ? "mesh" + std::to_string(mesh_index) : mesh.name;
      if (mesh.primitives.size() > 1) out.name += "." + std::to_string(p);
      out.positions = reader.readVec<3>(pos_it->second, field + ".attributes.POSITION");
      const std::size_t n = out.positions.size();
      for (std::size_t i = 0; i < n; ++i)
        if (!isFinite(out.positions[i]))
          reader.fail(field + ".attributes.POSITION", "finite positions",
                      "NaN or Inf at vertex " + std::to_string(i));
      if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
        out.normals = reader.readVec<3>(it->second, field + ".attributes.NORMAL");
        if (out.normals.size() != n) reader.fail(field + ".attributes.NORMAL", "one normal per position");
      }
      if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
        out.uvs = reader.readVec<2>(it->second, field + ".attributes.TEXCOORD_0");
        if (out.uvs.size() != n) reader.fail(field + ".attributes.TEXCOORD_0", "one uv per position");
      }
      std::vector<std::uint32_t> idx;
      if (prim.indices >= 0) {
        idx = reader.readIndices(prim.indices, field + ".indices");
        for (std::size_t i = 0; i < idx.size(); ++i)
          if (idx[i] >= n)
            reader.fail(field + ".indices", "indices < vertex count " + std::to_string(n),
                        "index " + std::to_string(idx[i]) + " at position " + std::to_string(i));
      } else {
        idx.resize(n);
        for (std::size_t i = 0; i < n; ++i) idx[i] = static_cast<std::uint32_t>(i);
      }
      out.triangles = trianglesFromIndices(idx, prim.mode == -1 ? TINYGLTF_MODE_TRIANGLES : prim.mode, reader,
                                           field + ".indices");
      // Instances count: a node hierarchy can repeat one small mesh millions of times.
      total_triangles += out.triangles.size();
      total_vertices += n;
      if (total_triangles > kMaxGltfTriangles || total_vertices > kMaxGltfVertices)
        reader.fail(field,
                    "a model of at most " + std::to_string(kMaxGltfTriangles) + " triangles and " +
                        std::to_string(kMaxGltfVertices) + " vertices, instances included (decimate it)",
                    std::to_string(total_triangles) + " triangles and " + std::to_string(total_vertices) +
                        " vertices so far");
      // Sanitise normals: a zero or non-finite normal would poison shading; recompute all.
      bool normals_ok = !out.normals.empty();
      for (auto& nrm : out.normals) {
        const float len = glm::length(nrm);
        if (!std::isfinite(len) || len < 1e-6f) {
          normals_ok = false;
          break;
        }
        nrm /= len;
      }
      if (!normals_ok) out.computeNormals();
      if (prim.material >= 0 && prim.material < default_material) {
        out.material = prim.material;
      } else {
        out.material = default_material;
        used_default = true;
      }
      out.transform(T);
      model.meshes.push_back(std::move(out));
    }
  };

  std::size_t node_visits = 0;
  std::function<void(int, const mat4&, int)> visit = [&](int node_index, const mat4& parent, int depth) {
    if (node_index < 0 || node_index >= static_cast<int>(gltf.nodes.size()))
      reader.fail("nodes", "a node index < " + std::to_string(gltf.nodes.size()), std::to_string(node_index));
    if (depth > 256) reader.fail("nodes", "an acyclic node hierarchy", "depth > 256");
    // Nodes shared between parents multiply: a few hundred can stand for billions of visits.
    if (++node_visits > kMaxGltfNodeVisits)
      reader.fail("nodes", "at most " + std::to_string(kMaxGltfNodeVisits) + " node instances in the scene",
                  "more (nodes shared by many parents)");
    const auto& node = gltf.nodes[static_cast<std::size_t>(node_index)];
    const mat4 T = parent * nodeMatrix(node);
    if (node.mesh >= 0) addMesh(node.mesh, T);
    for (int child : node.children) visit(child, T, depth + 1);
  };

  if (!gltf.scenes.empty()) {
    const int scene = gltf.defaultScene >= 0 && gltf.defaultScene < static_cast<int>(gltf.scenes.size())
                          ? gltf.defaultScene
                          : 0;
    for (int root : gltf.scenes[static_cast<std::size_t>(scene)].nodes) visit(root, mat4(1.0f), 0);
  } else {
    for (int i = 0; i < static_cast<int>(gltf.meshes.size()); ++i) addMesh(i, mat4(1.0f));
  }
  if (used_default) {
    Material fallback;
    fallback.name = "default";
    model.materials.push_back(fallback);
  }
  if (model.meshes.empty()) throw InputError(file, "meshes", "at least one triangle mesh", "none");
  return model;
}

[[noreturn]] void loadFailed(const std::string& file, const std::string& err, bool draco) {
  if (draco)
    throw InputError(file, "extensionsRequired", "meshes without Draco compression (no Draco decoder)",
                     kDraco);
  const std::string low = lower(err);
  if (low.find("not found") != std::string::npos) {
    // tinygltf reports a missing external file by name only; its extension tells which it was.
    const bool image = low.find(".png") != std::string::npos || low.find(".jp") != std::string::npos ||
                       low.find("image") != std::string::npos;
    throw InputError(file, image ? "images" : "buffers", "every external file the glTF names, next to it",
                     firstLine(err));
  }
  const std::string field = low.find("buffer") != std::string::npos  ? "buffers"
                            : low.find("image") != std::string::npos ? "images"
                                                                     : "";
  throw InputError(file, field, "a valid glTF 2.0 file", firstLine(err));
}

// Textures are decoded by OpenCV (libpng, libjpeg-turbo: kept and patched by Debian), not by the
// stb_image copy tinygltf would compile into this file: the fuzzer found stb's JPEG Huffman
// tables writing past their end. OpenCV refuses images above OPENCV_IO_MAX_IMAGE_PIXELS before
// allocating (the kiosk unit sets it); a texture larger than kMaxGltfTextureSide is refused here.
bool decodeTexture(tinygltf::Image* image, const int image_index, std::string* err, std::string*, int, int,
                   const unsigned char* bytes, int size, void*) {
  const std::string which = "image " + std::to_string(image_index);
  // glTF allows PNG and JPEG; OpenCV would also try TIFF, WebP, PNM and more, so only those two
  // are handed to it.
  const bool png = size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0;
  const bool jpeg = size >= 3 && std::memcmp(bytes, "\xff\xd8\xff", 3) == 0;
  if (!png && !jpeg) {
    if (err) *err += which + ": not a PNG or JPEG image\n";
    return false;
  }
  cv::Mat decoded;
  try {
    decoded =
        cv::imdecode(cv::Mat(1, size, CV_8UC1, const_cast<unsigned char*>(bytes)), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    if (err) *err += which + ": " + e.what() + "\n";
    return false;
  }
  if (decoded.empty()) {
    if (err) *err += which + ": not a PNG or JPEG image OpenCV can decode\n";
    return false;
  }
  if (decoded.cols > kMaxGltfTextureSide || decoded.rows > kMaxGltfTextureSide) {
    if (err)
      *err += which + " is " + std::to_string(decoded.cols) + "x" + std::to_string(decoded.rows) +
              ", expected at most " + std::to_string(kMaxGltfTextureSide) + " pixels a side\n";
    return false;
  }
  if (decoded.depth() != CV_8U && decoded.depth() != CV_16U) decoded.convertTo(decoded, CV_8U);
  cv::Mat rgb;  // glTF images are RGB(A); OpenCV decodes to BGR(A)
  switch (decoded.channels()) {
    case 3:
      cv::cvtColor(decoded, rgb, cv::COLOR_BGR2RGB);
      break;
    case 4:
      cv::cvtColor(decoded, rgb, cv::COLOR_BGRA2RGBA);
      break;
    default:
      rgb = decoded;
  }
  if (!rgb.isContinuous()) rgb = rgb.clone();
  image->width = rgb.cols;
  image->height = rgb.rows;
  image->component = rgb.channels();
  image->bits = rgb.depth() == CV_16U ? 16 : 8;
  image->pixel_type =
      rgb.depth() == CV_16U ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image.assign(rgb.data, rgb.data + rgb.total() * rgb.elemSize());
  return true;
}

// True when the raw JSON chunk names the Draco extension (tinygltf may fail before we look).
bool mentionsDraco(const std::string& bytes) {
  return bytes.find(kDraco) != std::string::npos;
}

}  // namespace

Model loadGltf(const fs::path& path) {
  const std::string file = path.string();
  if (!fs::exists(path)) throw InputError(file, "", "an existing .gltf or .glb file", "not found");
  const std::string ext = lower(path.extension().string());
  if (ext != ".gltf" && ext != ".glb") throw InputError(file, "", "a .gltf or .glb file", ext);
  if (const auto bytes_on_disk = fs::file_size(path); bytes_on_disk > kMaxGltfFileBytes)
    throw InputError(file, "", "a glTF file of at most " + std::to_string(kMaxGltfFileBytes >> 20) + " MiB",
                     std::to_string(bytes_on_disk >> 20) + " MiB");
  const std::string bytes = readFile(path);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(decodeTexture, nullptr);
  tinygltf::Model gltf;
  std::string err, warn;
  const std::string base_dir = path.has_parent_path() ? path.parent_path().string() : ".";
  const bool ok = ext == ".glb"
                      ? loader.LoadBinaryFromMemory(&gltf, &err, &warn,
                                                    reinterpret_cast<const unsigned char*>(bytes.data()),
                                                    static_cast<unsigned int>(bytes.size()), base_dir)
                      : loader.LoadASCIIFromString(&gltf, &err, &warn, bytes.data(),
                                                   static_cast<unsigned int>(bytes.size()), base_dir);
  if (!warn.empty()) HOLO_LOG_DEBUG("{}: tinygltf: {}", file, firstLine(warn));
  if (!ok) loadFailed(file, err, mentionsDraco(bytes));
  return convert(gltf, file);
}

Model loadGlbFromMemory(const std::vector<std::uint8_t>& glb, const std::string& origin) {
  if (glb.size() > kMaxGltfFileBytes)
    throw InputError(origin, "", "a glTF file of at most " + std::to_string(kMaxGltfFileBytes >> 20) + " MiB",
                     std::to_string(glb.size() >> 20) + " MiB");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(decodeTexture, nullptr);
  tinygltf::Model gltf;
  std::string err, warn;
  if (!loader.LoadBinaryFromMemory(&gltf, &err, &warn, glb.data(), static_cast<unsigned int>(glb.size()), ""))
    loadFailed(origin, err, mentionsDraco(std::string(glb.begin(), glb.end())));
  return convert(gltf, origin);
}

namespace {

// Appends raw bytes to buffer 0 (4-byte aligned) and returns the new buffer view's index.
int appendView(tinygltf::Model& g, const void* data, std::size_t bytes, int target) {
  auto& buf = g.buffers[0].data;
  while (buf.size() % 4 != 0) buf.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buf.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buf.insert(buf.end(), p, p + bytes);
  g.bufferViews.push_back(view);
  return static_cast<int>(g.bufferViews.size() - 1);
}

int appendAccessor(tinygltf::Model& g, int view, int component, int type, std::size_t count) {
  tinygltf::Accessor acc;
  acc.bufferView = view;
  acc.componentType = component;
  acc.type = type;
  acc.count = count;
  g.accessors.push_back(acc);
  return static_cast<int>(g.accessors.size() - 1);
}

tinygltf::Model toGltf(const Model& model) {
  tinygltf::Model g;
  g.asset.version = "2.0";
  g.asset.generator = "holopyramid";
  g.buffers.emplace_back();
  bool emissive_strength = false;

  for (std::size_t t = 0; t < model.textures.size(); ++t) {
    std::vector<unsigned char> png;
    if (!cv::imencode(".png", model.textures[t], png))
      throw Error("could not encode texture " + std::to_string(t));
    tinygltf::Image image;
    image.mimeType = "image/png";
    image.bufferView = appendView(g, png.data(), png.size(), 0);
    g.images.push_back(image);
    tinygltf::Texture tex;
    tex.source = static_cast<int>(t);
    g.textures.push_back(tex);
  }
  for (const auto& m : model.materials) {
    tinygltf::Material mat;
    mat.name = m.name;
    mat.pbrMetallicRoughness.baseColorFactor = {m.base_color.r, m.base_color.g, m.base_color.b, 1.0};
    mat.pbrMetallicRoughness.metallicFactor = m.metallic;
    mat.pbrMetallicRoughness.roughnessFactor = m.roughness;
    mat.pbrMetallicRoughness.baseColorTexture.index = m.base_color_texture;
    mat.pbrMetallicRoughness.metallicRoughnessTexture.index = m.metallic_roughness_texture;
    const float peak = std::max({m.emission.r, m.emission.g, m.emission.b});
    if (peak > 0.0f) {
      const float strength = std::max(peak, 1.0f);
      mat.emissiveFactor = {m.emission.r / strength, m.emission.g / strength, m.emission.b / strength};
      if (strength > 1.0f) {
        tinygltf::Value::Object ext;
        ext["emissiveStrength"] = tinygltf::Value(static_cast<double>(strength));
        mat.extensions[kEmissiveStrength] = tinygltf::Value(ext);
        emissive_strength = true;
      }
    }
    g.materials.push_back(mat);
  }
  tinygltf::Scene scene;
  for (const auto& mesh : model.meshes) {
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material = mesh.material;
    const std::size_t n = mesh.positions.size();
    const int pos = appendAccessor(
        g, appendView(g, mesh.positions.data(), n * sizeof(vec3), TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
    const Bounds3 b = mesh.bounds();
    if (!b.empty()) {
      g.accessors[static_cast<std::size_t>(pos)].minValues = {b.lo.x, b.lo.y, b.lo.z};
      g.accessors[static_cast<std::size_t>(pos)].maxValues = {b.hi.x, b.hi.y, b.hi.z};
    }
    prim.attributes["POSITION"] = pos;
    if (mesh.normals.size() == n)
      prim.attributes["NORMAL"] = appendAccessor(
          g, appendView(g, mesh.normals.data(), n * sizeof(vec3), TINYGLTF_TARGET_ARRAY_BUFFER),
          TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
    if (mesh.uvs.size() == n)
      prim.attributes["TEXCOORD_0"] =
          appendAccessor(g, appendView(g, mesh.uvs.data(), n * sizeof(vec2), TINYGLTF_TARGET_ARRAY_BUFFER),
                         TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, n);
    prim.indices =
        appendAccessor(g,
                       appendView(g, mesh.triangles.data(), mesh.triangles.size() * sizeof(uvec3),
                                  TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, mesh.triangles.size() * 3);
    tinygltf::Mesh gm;
    gm.name = mesh.name;
    gm.primitives.push_back(prim);
    g.meshes.push_back(gm);
    tinygltf::Node node;
    node.name = mesh.name;
    node.mesh = static_cast<int>(g.meshes.size() - 1);
    g.nodes.push_back(node);
    scene.nodes.push_back(static_cast<int>(g.nodes.size() - 1));
  }
  g.scenes.push_back(scene);
  g.defaultScene = 0;
  if (emissive_strength) g.extensionsUsed.push_back(kEmissiveStrength);
  return g;
}

std::string serialize(const Model& model, bool binary) {
  const tinygltf::Model g = toGltf(model);
  tinygltf::TinyGLTF writer;
  std::ostringstream out;
  if (!writer.WriteGltfSceneToStream(&g, out, !binary, binary))
    throw Error("tinygltf could not serialise the model");
  return out.str();
}

}  // namespace

std::vector<std::uint8_t> encodeGlb(const Model& model) {
  const std::string bytes = serialize(model, true);
  return {bytes.begin(), bytes.end()};
}

void saveGltf(const fs::path& path, const Model& model) {
  const std::string ext = lower(path.extension().string());
  if (ext != ".gltf" && ext != ".glb") throw InputError(path.string(), "", "a .gltf or .glb file name", ext);
  writeFileAtomically(path, serialize(model, ext == ".glb"));
}

}  // namespace holo
