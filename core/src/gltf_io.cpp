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
#include <array>
#include <cstring>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/log.hpp"
#include "holo/core/skinned_mesh.hpp"
#include "holo/core/stats.hpp"

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

  // `components` floats per element (FLOAT, or normalised integers of any glTF type), with the
  // accessor's type checked to have that many components.
  std::vector<float> readFloats(int accessor_index, const std::string& field, int components,
                                const std::string& type_name) const {
    if (accessor_index < 0 || accessor_index >= static_cast<int>(gltf_.accessors.size()))
      fail(field, "an accessor index < " + std::to_string(gltf_.accessors.size()),
           std::to_string(accessor_index));
    const auto& acc = accessor(accessor_index);
    if (tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type)) != components)
      fail(field, "a " + type_name + " accessor");
    if (acc.count > kMaxGltfVertices)
      fail(field, "at most " + std::to_string(kMaxGltfVertices) + " elements", std::to_string(acc.count));
    const int ct = acc.componentType;
    const Span elements = span(accessor_index, field);
    std::vector<float> out(elements.count * static_cast<std::size_t>(components));
    forEach(elements, [&](std::size_t i, const unsigned char* p) {
      for (int k = 0; k < components; ++k) {
        float v = 0;
        switch (ct) {
          case TINYGLTF_COMPONENT_TYPE_FLOAT:
            std::memcpy(&v, p + 4 * k, 4);
            break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            v = p[k] / 255.0f;
            break;
          case TINYGLTF_COMPONENT_TYPE_BYTE:
            v = std::max(static_cast<float>(static_cast<std::int8_t>(p[k])) / 127.0f, -1.0f);
            break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            std::uint16_t u;
            std::memcpy(&u, p + 2 * k, 2);
            v = u / 65535.0f;
            break;
          }
          case TINYGLTF_COMPONENT_TYPE_SHORT: {
            std::int16_t u;
            std::memcpy(&u, p + 2 * k, 2);
            v = std::max(u / 32767.0f, -1.0f);
            break;
          }
          default:
            fail(field, "FLOAT or normalised integer components", "componentType " + std::to_string(ct));
        }
        if (!std::isfinite(v)) fail(field, "finite numbers", "NaN or Inf in element " + std::to_string(i));
        out[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(k)] = v;
      }
    });
    return out;
  }

  // JOINTS_n: VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT (not normalised).
  std::vector<glm::uvec4> readJoints(int accessor_index, const std::string& field) const {
    if (accessor_index < 0 || accessor_index >= static_cast<int>(gltf_.accessors.size()))
      fail(field, "an accessor index < " + std::to_string(gltf_.accessors.size()),
           std::to_string(accessor_index));
    const auto& acc = accessor(accessor_index);
    if (acc.type != TINYGLTF_TYPE_VEC4) fail(field, "a VEC4 accessor");
    const int ct = acc.componentType;
    if (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
      fail(field, "UNSIGNED_BYTE or UNSIGNED_SHORT joint indices", "componentType " + std::to_string(ct));
    if (acc.count > kMaxGltfVertices)
      fail(field, "at most " + std::to_string(kMaxGltfVertices) + " vertices", std::to_string(acc.count));
    const Span elements = span(accessor_index, field);
    std::vector<glm::uvec4> out(elements.count);
    forEach(elements, [&](std::size_t i, const unsigned char* p) {
      for (int k = 0; k < 4; ++k) {
        if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
          out[i][k] = p[k];
        } else {
          std::uint16_t u;
          std::memcpy(&u, p + 2 * k, 2);
          out[i][k] = u;
        }
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

constexpr const char* kTextureTransform = "KHR_texture_transform";
constexpr const char* kSpecular = "KHR_materials_specular";
constexpr const char* kClearcoat = "KHR_materials_clearcoat";
constexpr const char* kTransmission = "KHR_materials_transmission";
constexpr const char* kVolume = "KHR_materials_volume";
constexpr const char* kIor = "KHR_materials_ior";

// The extensions whose every property convert() reads into holo::Material.
bool readsExtension(const std::string& name) {
  for (const char* known :
       {kEmissiveStrength, kTextureTransform, kSpecular, kClearcoat, kTransmission, kVolume, kIor})
    if (name == known) return true;
  return false;
}

TextureWrap wrapMode(int gl_wrap) {
  switch (gl_wrap) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
      return TextureWrap::ClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
      return TextureWrap::MirroredRepeat;
    default:
      return TextureWrap::Repeat;
  }
}

// glTF leaves unset filters to the viewer: bilinear with blended mips, the one that never aliases.
TextureSampler samplerFrom(const tinygltf::Sampler& s) {
  TextureSampler out;
  out.wrap_u = wrapMode(s.wrapS);
  out.wrap_v = wrapMode(s.wrapT);
  out.magnify_linear = s.magFilter != TINYGLTF_TEXTURE_FILTER_NEAREST;
  switch (s.minFilter) {
    case TINYGLTF_TEXTURE_FILTER_NEAREST:
    case TINYGLTF_TEXTURE_FILTER_LINEAR:
      out.use_mips = false;
      out.minify_linear = s.minFilter == TINYGLTF_TEXTURE_FILTER_LINEAR;
      break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST:
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST:
      out.blend_mips = false;
      out.minify_linear = s.minFilter == TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST;
      break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR:
      out.minify_linear = false;
      break;
    default:
      break;
  }
  return out;
}

// An index as JSON states it; -1 for anything that is not a whole number in int range (then
// rejected by the caller's range check).
int smallInteger(const tinygltf::Value& v) {
  if (!v.IsNumber()) return -1;
  const double d = v.GetNumberAsDouble();
  return d >= 0.0 && d < 1e9 && d == std::floor(d) ? static_cast<int>(d) : -1;
}

// glTF's colour slots hold sRGB-encoded colour; every other slot holds linear data.
TextureEncoding encodingOf(const std::string& field) {
  for (const char* colour_slot : {"baseColorTexture", "emissiveTexture", "specularColorTexture"})
    if (field.size() >= std::strlen(colour_slot) &&
        field.compare(field.size() - std::strlen(colour_slot), std::string::npos, colour_slot) == 0)
      return TextureEncoding::Srgb;
  return TextureEncoding::Linear;
}

// Reads one material's factors and texture references, rejecting what no renderer could use.
class MaterialReader {
 public:
  MaterialReader(const tinygltf::Model& gltf, const std::string& file, std::size_t index,
                 const std::function<int(int, TextureEncoding)>& texture_for)
      : file_(file), texture_for_(texture_for) {
    const auto& m = gltf.materials[index];
    where_ = "materials[" + std::to_string(index) + "]" + (m.name.empty() ? "" : " (\"" + m.name + "\")");
  }

  // A factor that must be finite and >= 0; those glTF bounds by 1 are clamped there, counted.
  float factor(double value, const std::string& field, bool at_most_one) const {
    if (!std::isfinite(value) || value < 0.0)
      throw InputError(file_, where_ + "." + field, "a finite number >= 0", std::to_string(value));
    if (at_most_one && value > 1.0) {
      stats::add("glTF/Material factors clamped to 1");
      HOLO_LOG_WARN("{}: {}.{} = {} is above 1: clamped to 1", file_, where_, field, value);
      return 1.0f;
    }
    return static_cast<float>(value);
  }

  float number(const tinygltf::Value& object, const char* key, float fallback, const std::string& field,
               bool at_most_one) const {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const auto& v = object.Get(key);
    if (!v.IsNumber()) throw InputError(file_, where_ + "." + field, "a number", "another JSON type");
    return factor(v.GetNumberAsDouble(), field, at_most_one);
  }

  vec3 colour(const std::vector<double>& rgb, const std::string& field, bool at_most_one) const {
    vec3 out;
    for (int k = 0; k < 3; ++k)
      out[k] = factor(rgb[static_cast<std::size_t>(k)], field + "[" + std::to_string(k) + "]", at_most_one);
    return out;
  }

  vec3 colour(const tinygltf::Value& object, const char* key, vec3 fallback, const std::string& field,
              bool at_most_one) const {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const auto& v = object.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 3)
      throw InputError(file_, where_ + "." + field, "an array of 3 numbers");
    std::vector<double> rgb;
    for (int k = 0; k < 3; ++k) {
      if (!v.Get(k).IsNumber())
        throw InputError(file_, where_ + "." + field + "[" + std::to_string(k) + "]", "a number");
      rgb.push_back(v.Get(k).GetNumberAsDouble());
    }
    return colour(rgb, field, at_most_one);
  }

  TextureRef texture(int index, int tex_coord, const tinygltf::ExtensionMap& extensions,
                     const std::string& field) const {
    TextureRef ref;
    if (index < 0) return ref;
    ref.index = texture_for_(index, encodingOf(field));
    if (ref.index < 0) return ref;
    ref.tex_coord = texCoord(tex_coord, field + ".texCoord");
    if (auto it = extensions.find(kTextureTransform); it != extensions.end()) {
      const tinygltf::Value& t = it->second;
      const std::string ext = field + ".extensions." + kTextureTransform;
      ref.offset = vec2(signedNumber(t, "offset", 0, 0.0f, ext), signedNumber(t, "offset", 1, 0.0f, ext));
      ref.scale = vec2(signedNumber(t, "scale", 0, 1.0f, ext), signedNumber(t, "scale", 1, 1.0f, ext));
      ref.rotation = signedNumber(t, "rotation", -1, 0.0f, ext);
      if (t.IsObject() && t.Has("texCoord")) {
        const auto& v = t.Get("texCoord");
        ref.tex_coord = texCoord(smallInteger(v), ext + ".texCoord");
      }
    }
    return ref;
  }

  // A textureInfo inside an extension object (tinygltf leaves those as JSON values).
  TextureRef texture(const tinygltf::Value& object, const char* key, const std::string& field,
                     float* scale = nullptr) const {
    if (!object.IsObject() || !object.Has(key)) return {};
    const auto& info = object.Get(key);
    const std::string f = field + "." + key;
    if (!info.IsObject() || !info.Has("index") || !info.Get("index").IsNumber())
      throw InputError(file_, where_ + "." + f + ".index", "a texture index");
    const int index = smallInteger(info.Get("index"));
    if (index < 0) throw InputError(file_, where_ + "." + f + ".index", "a texture index >= 0");
    const int tex_coord = info.Has("texCoord") ? smallInteger(info.Get("texCoord")) : 0;
    tinygltf::ExtensionMap extensions;
    if (info.Has("extensions") && info.Get("extensions").IsObject()) {
      const auto& e = info.Get("extensions");
      for (const auto& k : e.Keys()) extensions[k] = e.Get(k);
    }
    if (scale && info.Has("scale")) *scale = signedNumber(info, "scale", -1, 1.0f, f);
    return texture(index, tex_coord, extensions, f);
  }

  int texCoord(int value, const std::string& field) const {
    if (value != 0 && value != 1)
      throw InputError(file_, where_ + "." + field, "texture coordinate set 0 or 1", std::to_string(value));
    return value;
  }

  // A finite number that may be negative (offsets, rotations, scales); `k` >= 0 picks an array entry.
  float signedNumber(const tinygltf::Value& object, const char* key, int k, float fallback,
                     const std::string& field) const {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const std::string f = where_ + "." + field + "." + key + (k >= 0 ? "[" + std::to_string(k) + "]" : "");
    const auto& whole = object.Get(key);
    if (k >= 0 && (!whole.IsArray() || whole.ArrayLen() != 2))
      throw InputError(file_, f, "an array of 2 numbers");
    const auto& v = k >= 0 ? whole.Get(k) : whole;
    if (!v.IsNumber()) throw InputError(file_, f, "a number");
    const double d = v.GetNumberAsDouble();
    if (!std::isfinite(d)) throw InputError(file_, f, "a finite number", std::to_string(d));
    return static_cast<float>(d);
  }

  const std::string& file() const { return file_; }
  const std::string& where() const { return where_; }

 private:
  const std::string& file_;
  const std::function<int(int, TextureEncoding)>& texture_for_;
  std::string where_;
};

Material readMaterial(const tinygltf::Model& gltf, std::size_t index, const MaterialReader& r) {
  const auto& m = gltf.materials[index];
  const tinygltf::Value none;
  const auto extension = [&](const char* name) -> const tinygltf::Value& {
    const auto it = m.extensions.find(name);
    return it == m.extensions.end() ? none : it->second;
  };
  Material mat;
  mat.name = m.name;
  const auto& pbr = m.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() == 4) {
    mat.base_colour = r.colour(pbr.baseColorFactor, "pbrMetallicRoughness.baseColorFactor", true);
    mat.alpha = r.factor(pbr.baseColorFactor[3], "pbrMetallicRoughness.baseColorFactor[3]", true);
  } else if (!pbr.baseColorFactor.empty()) {
    throw InputError(r.file(), r.where() + ".pbrMetallicRoughness.baseColorFactor", "4 numbers (RGBA)",
                     std::to_string(pbr.baseColorFactor.size()));
  }
  mat.metallic = r.factor(pbr.metallicFactor, "pbrMetallicRoughness.metallicFactor", true);
  mat.roughness = r.factor(pbr.roughnessFactor, "pbrMetallicRoughness.roughnessFactor", true);
  mat.base_colour_texture =
      r.texture(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions,
                "pbrMetallicRoughness.baseColorTexture");
  mat.metallic_roughness_texture =
      r.texture(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                pbr.metallicRoughnessTexture.extensions, "pbrMetallicRoughness.metallicRoughnessTexture");

  const float strength =
      r.number(extension(kEmissiveStrength), "emissiveStrength", 1.0f,
               std::string("extensions.") + kEmissiveStrength + ".emissiveStrength", false);
  if (m.emissiveFactor.size() == 3)
    mat.emission = strength * r.colour(m.emissiveFactor, "emissiveFactor", true);
  mat.emissive_texture = r.texture(m.emissiveTexture.index, m.emissiveTexture.texCoord,
                                   m.emissiveTexture.extensions, "emissiveTexture");

  mat.normal_texture =
      r.texture(m.normalTexture.index, m.normalTexture.texCoord, m.normalTexture.extensions, "normalTexture");
  if (!std::isfinite(m.normalTexture.scale))
    throw InputError(r.file(), r.where() + ".normalTexture.scale", "a finite number",
                     std::to_string(m.normalTexture.scale));
  mat.normal_scale = static_cast<float>(m.normalTexture.scale);
  mat.occlusion_texture = r.texture(m.occlusionTexture.index, m.occlusionTexture.texCoord,
                                    m.occlusionTexture.extensions, "occlusionTexture");
  mat.occlusion_strength = r.factor(m.occlusionTexture.strength, "occlusionTexture.strength", true);

  if (m.alphaMode == "MASK") {
    mat.alpha_mode = AlphaMode::Mask;
  } else if (m.alphaMode == "BLEND") {
    mat.alpha_mode = AlphaMode::Blend;
  } else if (!m.alphaMode.empty() && m.alphaMode != "OPAQUE") {
    throw InputError(r.file(), r.where() + ".alphaMode", "OPAQUE, MASK or BLEND", m.alphaMode);
  }
  mat.alpha_cutoff = r.factor(m.alphaCutoff, "alphaCutoff", false);
  mat.double_sided = m.doubleSided;

  const std::string ext = "extensions.";
  const tinygltf::Value& spec = extension(kSpecular);
  const std::string spec_field = ext + kSpecular;
  mat.specular = r.number(spec, "specularFactor", 1.0f, spec_field + ".specularFactor", true);
  mat.specular_colour =
      r.colour(spec, "specularColorFactor", vec3(1.0f), spec_field + ".specularColorFactor", false);
  mat.specular_texture = r.texture(spec, "specularTexture", spec_field);
  mat.specular_colour_texture = r.texture(spec, "specularColorTexture", spec_field);

  const tinygltf::Value& coat = extension(kClearcoat);
  const std::string coat_field = ext + kClearcoat;
  mat.clearcoat = r.number(coat, "clearcoatFactor", 0.0f, coat_field + ".clearcoatFactor", true);
  mat.clearcoat_roughness =
      r.number(coat, "clearcoatRoughnessFactor", 0.0f, coat_field + ".clearcoatRoughnessFactor", true);
  mat.clearcoat_texture = r.texture(coat, "clearcoatTexture", coat_field);
  mat.clearcoat_roughness_texture = r.texture(coat, "clearcoatRoughnessTexture", coat_field);
  mat.clearcoat_normal_texture =
      r.texture(coat, "clearcoatNormalTexture", coat_field, &mat.clearcoat_normal_scale);

  const tinygltf::Value& transmission = extension(kTransmission);
  const std::string transmission_field = ext + kTransmission;
  mat.transmission =
      r.number(transmission, "transmissionFactor", 0.0f, transmission_field + ".transmissionFactor", true);
  mat.transmission_texture = r.texture(transmission, "transmissionTexture", transmission_field);

  const tinygltf::Value& volume = extension(kVolume);
  const std::string volume_field = ext + kVolume;
  mat.thickness = r.number(volume, "thicknessFactor", 0.0f, volume_field + ".thicknessFactor", false);
  mat.thickness_texture = r.texture(volume, "thicknessTexture", volume_field);
  mat.attenuation_colour =
      r.colour(volume, "attenuationColor", vec3(1.0f), volume_field + ".attenuationColor", true);
  if (volume.IsObject() && volume.Has("attenuationDistance")) {
    mat.attenuation_distance =
        r.number(volume, "attenuationDistance", 0.0f, volume_field + ".attenuationDistance", false);
    if (!(mat.attenuation_distance > 0.0f))
      throw InputError(r.file(), r.where() + "." + volume_field + ".attenuationDistance",
                       "a distance > 0 (omit it for clear glass)", "0");
  }

  const tinygltf::Value& ior = extension(kIor);
  mat.ior = r.number(ior, "ior", 1.5f, ext + kIor + ".ior", false);
  if (mat.ior < 1.0f)
    throw InputError(r.file(), r.where() + "." + ext + kIor + ".ior", "an index of refraction >= 1",
                     std::to_string(mat.ior));
  return mat;
}

// Where a loaded TriangleMesh came from, for the skinned loader (which keeps meshes in their own
// space and poses them itself).
struct MeshSource {
  int node = -1;  // -1: a file without scenes
  int mesh = -1;
  int primitive = -1;
};

// With `sources`, meshes stay in their own space (node transforms not applied) and their
// origins are listed in mesh order.
Model convert(const tinygltf::Model& gltf, const std::string& file,
              std::vector<MeshSource>* sources = nullptr) {
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
  const Reader reader(gltf, file);
  Model model;

  // Textures: (glTF texture index, encoding) -> Model::textures index (decoded, mip chain built,
  // once). A texture a colour slot and a data slot both use is built once per encoding.
  std::vector<std::array<int, 2>> texture_slot(gltf.textures.size(), {-1, -1});
  const std::function<int(int, TextureEncoding)> textureFor = [&](int gltf_texture,
                                                                  TextureEncoding encoding) -> int {
    if (gltf_texture < 0 || gltf_texture >= static_cast<int>(gltf.textures.size()))
      reader.fail("textures", "a texture index < " + std::to_string(gltf.textures.size()),
                  std::to_string(gltf_texture));
    auto& slot = texture_slot[static_cast<std::size_t>(gltf_texture)][encoding == TextureEncoding::Srgb];
    if (slot >= 0) return slot;
    const auto& texture = gltf.textures[static_cast<std::size_t>(gltf_texture)];
    const int source = texture.source;
    if (source < 0 || source >= static_cast<int>(gltf.images.size())) {
      stats::add("glTF/Textures ignored");
      HOLO_LOG_WARN("{}: textures[{}] has no image this build decodes (source {}): texture ignored", file,
                    gltf_texture, source);
      return -1;
    }
    cv::Mat decoded = decodeImage(gltf.images[static_cast<std::size_t>(source)]);
    if (decoded.empty()) {
      stats::add("glTF/Textures ignored");
      HOLO_LOG_WARN("{}: images[{}]: could not decode, texture ignored", file, source);
      return -1;
    }
    TextureSampler sampler;
    if (texture.sampler >= 0) {
      if (texture.sampler >= static_cast<int>(gltf.samplers.size()))
        reader.fail("textures[" + std::to_string(gltf_texture) + "].sampler",
                    "a sampler index < " + std::to_string(gltf.samplers.size()),
                    std::to_string(texture.sampler));
      sampler = samplerFrom(gltf.samplers[static_cast<std::size_t>(texture.sampler)]);
    }
    slot = static_cast<int>(model.textures.size());
    model.textures.emplace_back(std::move(decoded), sampler, encoding);
    return slot;
  };

  for (std::size_t i = 0; i < gltf.materials.size(); ++i)
    model.materials.push_back(readMaterial(gltf, i, MaterialReader(gltf, file, i, textureFor)));
  const int default_material = static_cast<int>(model.materials.size());
  bool used_default = false;
  std::size_t total_triangles = 0;
  std::size_t total_vertices = 0;

  auto addMesh = [&](int mesh_index, const mat4& T, int node_index) {
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
      if (auto it = prim.attributes.find("TEXCOORD_1"); it != prim.attributes.end()) {
        out.uvs1 = reader.readVec<2>(it->second, field + ".attributes.TEXCOORD_1");
        if (out.uvs1.size() != n) reader.fail(field + ".attributes.TEXCOORD_1", "one uv per position");
      }
      if (auto it = prim.attributes.find("TANGENT"); it != prim.attributes.end()) {
        out.tangents = reader.readVec<4>(it->second, field + ".attributes.TANGENT");
        if (out.tangents.size() != n) reader.fail(field + ".attributes.TANGENT", "one tangent per position");
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
      const Material* mat = out.material < default_material
                                ? &model.materials[static_cast<std::size_t>(out.material)]
                                : nullptr;
      const TextureRef* normal_map = nullptr;
      if (mat && mat->normal_texture.used()) {
        normal_map = &mat->normal_texture;
      } else if (mat && mat->clearcoat_normal_texture.used()) {
        normal_map = &mat->clearcoat_normal_texture;
      }
      // Tangents from the file are used when they are finite with unit xyz and w = +-1, and when
      // the normals they go with were kept; otherwise the glTF specification asks for MikkTSpace.
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
            file, field);
      }
      if (tangents_ok) {
        for (std::size_t i = 0; i < n; ++i) {
          const vec3 nv = out.normals[i];
          const vec3 t = vec3(out.tangents[i]) - nv * glm::dot(nv, vec3(out.tangents[i]));
          out.tangents[i] = vec4(glm::normalize(t), out.tangents[i].w < 0.0f ? -1.0f : 1.0f);
        }
      } else if (normal_map || !out.tangents.empty() || !out.uvs.empty()) {
        // Every textured primitive gets a tangent frame, so a renderer never meets a material
        // whose maps it cannot orient.
        out.computeTangents(normal_map ? normal_map->tex_coord : 0);
      }
      if (sources) {
        sources->push_back({node_index, mesh_index, static_cast<int>(p)});
      } else {
        out.transform(T);
      }
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
    if (node.mesh >= 0) addMesh(node.mesh, T, node_index);
    for (int child : node.children) visit(child, T, depth + 1);
  };

  if (!gltf.scenes.empty()) {
    const int scene = gltf.defaultScene >= 0 && gltf.defaultScene < static_cast<int>(gltf.scenes.size())
                          ? gltf.defaultScene
                          : 0;
    for (int root : gltf.scenes[static_cast<std::size_t>(scene)].nodes) visit(root, mat4(1.0f), 0);
  } else {
    for (int i = 0; i < static_cast<int>(gltf.meshes.size()); ++i) addMesh(i, mat4(1.0f), -1);
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

namespace {

// External files (buffers, images) a glTF names are read only from inside the glTF's own folder:
// a relic from outside must not make the appliance read /etc/passwd, a file next to the program
// (tinygltf also searches the working directory) or one a symlink leads to. These callbacks
// replace tinygltf's file system; the first URI that points outside is kept for the error.
struct ExternalFileScope {
  std::string base;    // the search folder given to tinygltf: canonical, or empty (nothing external)
  fs::path folder;     // the same folder as a path
  std::string escape;  // the first URI that led outside `folder`
};

// The file `joined` (tinygltf's search folder + "/" + the decoded URI) resolves to, when it lies
// inside the glTF's folder; empty otherwise (tinygltf's other search folder, ".", is never used).
fs::path resolveInside(ExternalFileScope& scope, const std::string& joined) {
  const std::string prefix = scope.base.empty() || scope.base.back() == '/' ? scope.base : scope.base + "/";
  if (scope.base.empty() || joined.rfind(prefix, 0) != 0) {
    if (scope.base.empty() && scope.escape.empty()) scope.escape = joined;  // no folder at all
    return {};
  }
  const std::string uri = joined.substr(prefix.size());
  std::error_code error;
  const fs::path resolved = fs::weakly_canonical(scope.folder / uri, error);
  const fs::path inside = resolved.lexically_relative(scope.folder);
  const bool escapes =
      uri.empty() || fs::path(uri).is_absolute() || error || inside.empty() || *inside.begin() == "..";
  if (escapes) {
    if (scope.escape.empty()) scope.escape = uri;
    return {};
  }
  return resolved;
}

bool externalFileExists(const std::string& joined, void* user) {
  const fs::path file = resolveInside(*static_cast<ExternalFileScope*>(user), joined);
  std::error_code error;
  return !file.empty() && fs::is_regular_file(file, error);
}

std::string keepFilePath(const std::string& path, void*) {
  return path;  // no ~ or $VAR expansion in a URI
}

bool readExternalFile(std::vector<unsigned char>* out, std::string* err, const std::string& joined,
                      void* user) {
  const fs::path file = resolveInside(*static_cast<ExternalFileScope*>(user), joined);
  std::error_code error;
  const auto bytes = file.empty() ? 0 : fs::file_size(file, error);
  if (file.empty() || error || bytes > kMaxGltfFileBytes) {
    *err =
        "outside the glTF's folder, unreadable or over " + std::to_string(kMaxGltfFileBytes >> 20) + " MiB";
    return false;
  }
  const std::string text = readFile(file);
  out->assign(text.begin(), text.end());
  return true;
}

bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  *err = "the loader writes no files";
  return false;
}

// Loads with external files confined to `folder` (empty: a glTF from memory, nothing external).
bool loadConfined(tinygltf::TinyGLTF& loader, tinygltf::Model& gltf, std::string& err, std::string& warn,
                  const unsigned char* bytes, std::size_t size, bool binary, const fs::path& folder,
                  const std::string& file) {
  ExternalFileScope scope;
  if (!folder.empty()) {
    std::error_code error;
    scope.folder = fs::canonical(folder, error);
    if (error) throw InputError(file, "", "a glTF in a readable folder", error.message());
    scope.base = scope.folder.string();
  }
  loader.SetFsCallbacks({externalFileExists, keepFilePath, readExternalFile, refuseWrite, &scope});
  const auto length = static_cast<unsigned int>(size);
  const bool ok = binary ? loader.LoadBinaryFromMemory(&gltf, &err, &warn, bytes, length, scope.base)
                         : loader.LoadASCIIFromString(
                               &gltf, &err, &warn, reinterpret_cast<const char*>(bytes), length, scope.base);
  if (scope.escape.empty()) return ok;
  // Images that fail to load stay in the model with their URI; a failing buffer ends the load.
  std::string field = "buffers[" + std::to_string(gltf.buffers.size()) + "].uri";
  for (std::size_t i = 0; i < gltf.images.size(); ++i)
    if (!gltf.images[i].uri.empty() && gltf.images[i].image.empty() &&
        tinygltf::dlib::urldecode(gltf.images[i].uri) == scope.escape)
      field = "images[" + std::to_string(i) + "].uri";
  throw InputError(file, field,
                   folder.empty() ? "only embedded data in a glTF read from memory"
                                  : "a relative path inside the glTF's folder " + scope.base +
                                        " (no absolute path, no '..' or symlink leading out of it)",
                   scope.escape);
}

tinygltf::Model parseFile(const fs::path& path) {
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
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const bool ok = loadConfined(loader, gltf, err, warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                               bytes.size(), ext == ".glb", folder, file);
  if (!warn.empty()) HOLO_LOG_DEBUG("{}: tinygltf: {}", file, firstLine(warn));
  if (!ok) loadFailed(file, err, mentionsDraco(bytes));
  return gltf;
}

// Every extension convert() reads has its factors rendered by both renderers; their textures are
// listed per slot.
GltfSupport extensionSupport(const std::string& extension) {
  return readsExtension(extension) ? GltfSupport::Rendered : GltfSupport::Ignored;
}

}  // namespace

const char* describe(GltfSupport support) {
  switch (support) {
    case GltfSupport::Rendered:
      return "rendered";
    case GltfSupport::Ignored:
      return "ignored (not read by this build)";
  }
  return "";
}

Model loadGltf(const fs::path& path) {
  return convert(parseFile(path), path.string());
}

GltfInventory inspectGltf(const fs::path& path) {
  const tinygltf::Model gltf = parseFile(path);
  GltfInventory out;
  out.model = convert(gltf, path.string());
  std::vector<std::string> names = gltf.extensionsUsed;
  for (const auto& ext : gltf.extensionsRequired)
    if (std::find(names.begin(), names.end(), ext) == names.end()) names.push_back(ext);
  for (const auto& ext : names) {
    GltfFeature f;
    f.name = ext;
    f.support = extensionSupport(ext);
    f.required = std::find(gltf.extensionsRequired.begin(), gltf.extensionsRequired.end(), ext) !=
                 gltf.extensionsRequired.end();
    for (const auto& m : gltf.materials) f.materials += m.extensions.count(ext) ? 1 : 0;
    out.extensions.push_back(f);
  }
  const auto count = [&](std::vector<GltfFeature>& list, const std::string& name, GltfSupport support,
                         const std::function<bool(const Material&)>& uses) {
    GltfFeature f;
    f.name = name;
    f.support = support;
    for (const auto& m : out.model.materials) f.materials += uses(m) ? 1 : 0;
    if (f.materials > 0) list.push_back(f);
  };
  const std::pair<const char*, TextureRef Material::*> slots[] = {
      {"baseColorTexture", &Material::base_colour_texture},
      {"metallicRoughnessTexture", &Material::metallic_roughness_texture},
      {"normalTexture", &Material::normal_texture},
      {"occlusionTexture", &Material::occlusion_texture},
      {"emissiveTexture", &Material::emissive_texture},
      {"specularTexture", &Material::specular_texture},
      {"specularColorTexture", &Material::specular_colour_texture},
      {"clearcoatTexture", &Material::clearcoat_texture},
      {"clearcoatRoughnessTexture", &Material::clearcoat_roughness_texture},
      {"clearcoatNormalTexture", &Material::clearcoat_normal_texture},
      {"transmissionTexture", &Material::transmission_texture},
      {"thicknessTexture", &Material::thickness_texture}};
  for (const auto& slot : slots) {
    // Not a structured binding: clang 14 (the fuzz build) cannot capture one in a lambda.
    const auto member = slot.second;
    // Both renderers read every slot (reflect/surface_shading.hpp), through either uv set,
    // KHR_texture_transform and the sampler.
    count(out.texture_slots, slot.first, GltfSupport::Rendered,
          [&](const Material& m) { return (m.*member).used(); });
  }
  const auto anySlot = [&](const Material& m, const std::function<bool(const TextureRef&)>& test) {
    for (const auto& slot : slots)
      if (test(m.*(slot.second))) return true;
    return false;
  };
  const GltfSupport rendered = GltfSupport::Rendered;
  count(out.properties, "emissiveFactor (emission)", rendered,
        [](const Material& m) { return m.emission != vec3(0.0f); });
  count(out.properties, "alphaMode MASK", rendered,
        [](const Material& m) { return m.alpha_mode == AlphaMode::Mask; });
  count(out.properties, "alphaMode BLEND", rendered,
        [](const Material& m) { return m.alpha_mode == AlphaMode::Blend; });
  count(out.properties, "doubleSided", rendered, [](const Material& m) { return m.double_sided; });
  count(out.properties, "texCoord 1 (TEXCOORD_1)", rendered, [&](const Material& m) {
    return anySlot(m, [](const TextureRef& t) { return t.used() && t.tex_coord == 1; });
  });
  return out;
}

Model loadGlbFromMemory(const std::vector<std::uint8_t>& glb, const std::string& origin) {
  if (glb.size() > kMaxGltfFileBytes)
    throw InputError(origin, "", "a glTF file of at most " + std::to_string(kMaxGltfFileBytes >> 20) + " MiB",
                     std::to_string(glb.size() >> 20) + " MiB");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(decodeTexture, nullptr);
  tinygltf::Model gltf;
  std::string err, warn;
  if (!loadConfined(loader, gltf, err, warn, glb.data(), glb.size(), true, {}, origin))
    loadFailed(origin, err, mentionsDraco(std::string(glb.begin(), glb.end())));
  return convert(gltf, origin);
}

SkinnedModel loadSkinnedGltf(const fs::path& path) {
  const tinygltf::Model gltf = parseFile(path);
  const std::string file = path.string();
  const Reader reader(gltf, file);
  std::vector<MeshSource> sources;
  Model flat = convert(gltf, file, &sources);
  SkinnedModel out;
  out.materials = std::move(flat.materials);
  out.textures = std::move(flat.textures);

  // Every node, with its parent and rest transform; `order` puts parents first.
  Skeleton& skeleton = out.skeleton;
  const int node_count = static_cast<int>(gltf.nodes.size());
  skeleton.nodes.resize(gltf.nodes.size());
  for (int i = 0; i < node_count; ++i) {
    const auto& node = gltf.nodes[static_cast<std::size_t>(i)];
    SkeletonNode& n = skeleton.nodes[static_cast<std::size_t>(i)];
    n.name = node.name;
    const std::string field = "nodes[" + std::to_string(i) + "]";
    if (node.matrix.size() == 16) {
      n.matrix = nodeMatrix(node);
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

  for (std::size_t s = 0; s < gltf.skins.size(); ++s) {
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
    skeleton.skins.push_back(std::move(skin));
  }

  for (std::size_t i = 0; i < flat.meshes.size(); ++i) {
    const MeshSource& src = sources[i];
    SkinnedMesh sm;
    sm.mesh = std::move(flat.meshes[i]);
    sm.node = src.node;
    const int skin = src.node >= 0 ? gltf.nodes[static_cast<std::size_t>(src.node)].skin : -1;
    const auto& prim =
        gltf.meshes[static_cast<std::size_t>(src.mesh)].primitives[static_cast<std::size_t>(src.primitive)];
    const std::string field = "meshes[" + std::to_string(src.mesh) + "].primitives[" +
                              std::to_string(src.primitive) + "].attributes";
    const auto joints_it = prim.attributes.find("JOINTS_0");
    const auto weights_it = prim.attributes.find("WEIGHTS_0");
    if (skin >= static_cast<int>(skeleton.skins.size()))
      reader.fail("nodes[" + std::to_string(src.node) + "].skin",
                  "a skin index < " + std::to_string(skeleton.skins.size()), std::to_string(skin));
    if (skin >= 0 && joints_it != prim.attributes.end() && weights_it != prim.attributes.end()) {
      sm.skin = skin;
      const std::size_t n = sm.mesh.positions.size();
      const std::size_t joint_count = skeleton.skins[static_cast<std::size_t>(skin)].joints.size();
      sm.joints = reader.readJoints(joints_it->second, field + ".JOINTS_0");
      const std::vector<float> w = reader.readFloats(weights_it->second, field + ".WEIGHTS_0", 4, "VEC4");
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
    } else if (skin >= 0) {
      reader.fail(field, "JOINTS_0 and WEIGHTS_0 on a primitive of a skinned node", "missing");
    }
    out.meshes.push_back(std::move(sm));
  }

  for (std::size_t a = 0; a < gltf.animations.size(); ++a) {
    const auto& anim = gltf.animations[a];
    AnimationClip clip;
    clip.name = anim.name.empty() ? "animation" + std::to_string(a) : anim.name;
    for (std::size_t c = 0; c < anim.channels.size(); ++c) {
      const auto& ch = anim.channels[c];
      const std::string field = "animations[" + std::to_string(a) + "].channels[" + std::to_string(c) + "]";
      if (ch.target_path == "weights") {  // morph targets: this build has none to drive
        stats::add("glTF/Morph target animations ignored");
        HOLO_LOG_WARN("{}: {} animates morph target weights: ignored (not read)", file, field);
        continue;
      }
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
      clip.duration = std::max(clip.duration, out_channel.times.back());
      clip.channels.push_back(std::move(out_channel));
    }
    out.clips.push_back(std::move(clip));
  }
  return out;
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

int glWrap(TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge:
      return TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    case TextureWrap::MirroredRepeat:
      return TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;
    case TextureWrap::Repeat:
      break;
  }
  return TINYGLTF_TEXTURE_WRAP_REPEAT;
}

tinygltf::Sampler glSampler(const TextureSampler& s) {
  tinygltf::Sampler out;
  out.wrapS = glWrap(s.wrap_u);
  out.wrapT = glWrap(s.wrap_v);
  out.magFilter = s.magnify_linear ? TINYGLTF_TEXTURE_FILTER_LINEAR : TINYGLTF_TEXTURE_FILTER_NEAREST;
  if (!s.use_mips) {
    out.minFilter = s.minify_linear ? TINYGLTF_TEXTURE_FILTER_LINEAR : TINYGLTF_TEXTURE_FILTER_NEAREST;
  } else if (s.blend_mips) {
    out.minFilter = s.minify_linear ? TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR
                                    : TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR;
  } else {
    out.minFilter = s.minify_linear ? TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST
                                    : TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST;
  }
  return out;
}

// Collects what a material's texture references need written: KHR_texture_transform when a
// reference moves its uvs.
class TextureWriter {
 public:
  template <class Info>
  void fill(Info& info, const TextureRef& ref) {
    info.index = ref.index;
    info.texCoord = ref.tex_coord;
    if (auto t = transformOf(ref)) info.extensions[kTextureTransform] = *t;
  }
  tinygltf::Value value(const TextureRef& ref, std::optional<float> scale = std::nullopt) {
    tinygltf::Value::Object o;
    o["index"] = tinygltf::Value(ref.index);
    o["texCoord"] = tinygltf::Value(ref.tex_coord);
    if (scale) o["scale"] = tinygltf::Value(static_cast<double>(*scale));
    if (auto t = transformOf(ref)) {
      tinygltf::Value::Object e;
      e[kTextureTransform] = *t;
      o["extensions"] = tinygltf::Value(e);
    }
    return tinygltf::Value(o);
  }
  bool used() const { return used_; }

 private:
  std::optional<tinygltf::Value> transformOf(const TextureRef& ref) {
    if (ref.offset == vec2(0.0f) && ref.rotation == 0.0f && ref.scale == vec2(1.0f)) return std::nullopt;
    used_ = true;
    const auto pair = [](vec2 v) {
      return tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(static_cast<double>(v.x)),
                                                    tinygltf::Value(static_cast<double>(v.y))});
    };
    tinygltf::Value::Object t;
    t["offset"] = pair(ref.offset);
    t["rotation"] = tinygltf::Value(static_cast<double>(ref.rotation));
    t["scale"] = pair(ref.scale);
    return tinygltf::Value(t);
  }
  bool used_ = false;
};

tinygltf::Value number(double v) {
  return tinygltf::Value(v);
}
tinygltf::Value rgb(const vec3& c) {
  return tinygltf::Value(tinygltf::Value::Array{number(c.r), number(c.g), number(c.b)});
}

tinygltf::Model toGltf(const Model& model) {
  tinygltf::Model g;
  g.asset.version = "2.0";
  g.asset.generator = "holopyramid";
  g.buffers.emplace_back();
  std::set<std::string> extensions;

  for (std::size_t t = 0; t < model.textures.size(); ++t) {
    std::vector<unsigned char> png;
    if (model.textures[t].empty() || !cv::imencode(".png", model.textures[t].image(), png))
      throw Error("could not encode texture " + std::to_string(t));
    tinygltf::Image image;
    image.mimeType = "image/png";
    image.bufferView = appendView(g, png.data(), png.size(), 0);
    g.images.push_back(image);
    g.samplers.push_back(glSampler(model.textures[t].sampler));
    tinygltf::Texture tex;
    tex.source = static_cast<int>(t);
    tex.sampler = static_cast<int>(t);
    g.textures.push_back(tex);
  }
  TextureWriter textures;
  for (const auto& m : model.materials) {
    tinygltf::Material mat;
    mat.name = m.name;
    auto& pbr = mat.pbrMetallicRoughness;
    pbr.baseColorFactor = {m.base_colour.r, m.base_colour.g, m.base_colour.b, m.alpha};
    pbr.metallicFactor = m.metallic;
    pbr.roughnessFactor = m.roughness;
    if (m.base_colour_texture.used()) textures.fill(pbr.baseColorTexture, m.base_colour_texture);
    if (m.metallic_roughness_texture.used())
      textures.fill(pbr.metallicRoughnessTexture, m.metallic_roughness_texture);
    if (m.emissive_texture.used()) textures.fill(mat.emissiveTexture, m.emissive_texture);
    if (m.normal_texture.used()) {
      textures.fill(mat.normalTexture, m.normal_texture);
      mat.normalTexture.scale = m.normal_scale;
    }
    if (m.occlusion_texture.used()) {
      textures.fill(mat.occlusionTexture, m.occlusion_texture);
      mat.occlusionTexture.strength = m.occlusion_strength;
    }
    mat.alphaMode = m.alpha_mode == AlphaMode::Mask    ? "MASK"
                    : m.alpha_mode == AlphaMode::Blend ? "BLEND"
                                                       : "OPAQUE";
    mat.alphaCutoff = m.alpha_cutoff;
    mat.doubleSided = m.double_sided;
    const float peak = std::max({m.emission.r, m.emission.g, m.emission.b});
    if (peak > 0.0f) {
      const float strength = std::max(peak, 1.0f);
      mat.emissiveFactor = {m.emission.r / strength, m.emission.g / strength, m.emission.b / strength};
      if (strength > 1.0f) {
        tinygltf::Value::Object ext;
        ext["emissiveStrength"] = number(strength);
        mat.extensions[kEmissiveStrength] = tinygltf::Value(ext);
      }
    }
    const auto add = [&](const char* name, tinygltf::Value::Object object) {
      mat.extensions[name] = tinygltf::Value(std::move(object));
    };
    if (m.specular != 1.0f || m.specular_colour != vec3(1.0f) || m.specular_texture.used() ||
        m.specular_colour_texture.used()) {
      tinygltf::Value::Object o{{"specularFactor", number(m.specular)},
                                {"specularColorFactor", rgb(m.specular_colour)}};
      if (m.specular_texture.used()) o["specularTexture"] = textures.value(m.specular_texture);
      if (m.specular_colour_texture.used())
        o["specularColorTexture"] = textures.value(m.specular_colour_texture);
      add(kSpecular, std::move(o));
    }
    if (m.clearcoat > 0.0f || m.clearcoat_texture.used()) {
      tinygltf::Value::Object o{{"clearcoatFactor", number(m.clearcoat)},
                                {"clearcoatRoughnessFactor", number(m.clearcoat_roughness)}};
      if (m.clearcoat_texture.used()) o["clearcoatTexture"] = textures.value(m.clearcoat_texture);
      if (m.clearcoat_roughness_texture.used())
        o["clearcoatRoughnessTexture"] = textures.value(m.clearcoat_roughness_texture);
      if (m.clearcoat_normal_texture.used())
        o["clearcoatNormalTexture"] = textures.value(m.clearcoat_normal_texture, m.clearcoat_normal_scale);
      add(kClearcoat, std::move(o));
    }
    if (m.transmission > 0.0f || m.transmission_texture.used()) {
      tinygltf::Value::Object o{{"transmissionFactor", number(m.transmission)}};
      if (m.transmission_texture.used()) o["transmissionTexture"] = textures.value(m.transmission_texture);
      add(kTransmission, std::move(o));
    }
    if (m.thickness > 0.0f || m.thickness_texture.used() || std::isfinite(m.attenuation_distance)) {
      tinygltf::Value::Object o{{"thicknessFactor", number(m.thickness)},
                                {"attenuationColor", rgb(m.attenuation_colour)}};
      if (std::isfinite(m.attenuation_distance)) o["attenuationDistance"] = number(m.attenuation_distance);
      if (m.thickness_texture.used()) o["thicknessTexture"] = textures.value(m.thickness_texture);
      add(kVolume, std::move(o));
    }
    if (m.ior != 1.5f) add(kIor, {{"ior", number(m.ior)}});
    for (const auto& [name, value] : mat.extensions) extensions.insert(name);
    g.materials.push_back(mat);
  }
  if (textures.used()) extensions.insert(kTextureTransform);
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
    if (mesh.uvs1.size() == n)
      prim.attributes["TEXCOORD_1"] =
          appendAccessor(g, appendView(g, mesh.uvs1.data(), n * sizeof(vec2), TINYGLTF_TARGET_ARRAY_BUFFER),
                         TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, n);
    if (mesh.tangents.size() == n)
      prim.attributes["TANGENT"] = appendAccessor(
          g, appendView(g, mesh.tangents.data(), n * sizeof(vec4), TINYGLTF_TARGET_ARRAY_BUFFER),
          TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, n);
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
  g.extensionsUsed.assign(extensions.begin(), extensions.end());
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
