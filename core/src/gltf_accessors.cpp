#include "gltf_accessors.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "holo/core/error.hpp"
#include "holo/core/gltf_limits.hpp"

namespace holo::gltf_detail {

void AccessorReader::fail(const std::string& field, const std::string& expected,
                          const std::string& got) const {
  throw InputError(file_, field, expected, got);
}

const tinygltf::Accessor& AccessorReader::accessor(int accessor_index, const std::string& field) const {
  if (accessor_index < 0 || accessor_index >= static_cast<int>(gltf_.accessors.size()))
    fail(field, "an accessor index < " + std::to_string(gltf_.accessors.size()),
         std::to_string(accessor_index));
  return gltf_.accessors[static_cast<std::size_t>(accessor_index)];
}

AccessorReader::Span AccessorReader::span(int accessor_index, const std::string& field) const {
  const auto& acc = accessor(accessor_index, field);
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
  const int element_size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(acc.componentType)) *
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

void AccessorReader::forEach(const Span& s,
                             const std::function<void(std::size_t, const unsigned char*)>& visit) {
  for (std::size_t i = 0; i < s.count; ++i) visit(i, s.base + i * s.stride);
}

template <int N>
std::vector<glm::vec<N, float>> AccessorReader::readVec(int accessor_index, const std::string& field) const {
  std::vector<glm::vec<N, float>> out;
  const auto& acc = accessor(accessor_index, field);
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

template std::vector<glm::vec<2, float>> AccessorReader::readVec<2>(int, const std::string&) const;
template std::vector<glm::vec<3, float>> AccessorReader::readVec<3>(int, const std::string&) const;
template std::vector<glm::vec<4, float>> AccessorReader::readVec<4>(int, const std::string&) const;

std::vector<float> AccessorReader::readFloats(int accessor_index, const std::string& field, int components,
                                              const std::string& type_name) const {
  const auto& acc = accessor(accessor_index, field);
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

std::vector<glm::uvec4> AccessorReader::readJoints(int accessor_index, const std::string& field) const {
  const auto& acc = accessor(accessor_index, field);
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

std::vector<std::uint32_t> AccessorReader::readIndices(int accessor_index, const std::string& field) const {
  std::vector<std::uint32_t> out;
  const auto& acc = accessor(accessor_index, field);
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

}  // namespace holo::gltf_detail
