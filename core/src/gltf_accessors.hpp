// Bounds-checked reading of glTF accessors (internal to core). Every accessor is checked against
// its buffer view and buffer before anything is allocated for its elements, so a malformed file
// gives an InputError naming the file and the field instead of a read out of bounds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "gltf_tinygltf.hpp"
#include "holo/core/math.hpp"

namespace holo::gltf_detail {

class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& gltf, std::string file) : gltf_(gltf), file_(std::move(file)) {}

  const std::string& file() const { return file_; }

  // Throws InputError(file, field, expected, got).
  [[noreturn]] void fail(const std::string& field, const std::string& expected,
                         const std::string& got = {}) const;

  // A float vector attribute, N = 2, 3 or 4 (normalized integers allowed for texture
  // coordinates).
  template <int N>
  std::vector<glm::vec<N, float>> readVec(int accessor_index, const std::string& field) const;

  // `components` floats per element (FLOAT, or normalised integers of any glTF type), with the
  // accessor's type checked to have that many components (`type_name` names it in errors).
  std::vector<float> readFloats(int accessor_index, const std::string& field, int components,
                                const std::string& type_name) const;

  // JOINTS_n: VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT (not normalised).
  std::vector<glm::uvec4> readJoints(int accessor_index, const std::string& field) const;

  // Vertex indices: SCALAR of unsigned byte, short or int.
  std::vector<std::uint32_t> readIndices(int accessor_index, const std::string& field) const;

 private:
  // Where an accessor's elements lie, checked against its buffer view and buffer before anything
  // is allocated for them: `count` comes from the file and may claim billions.
  struct Span {
    const unsigned char* base = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
  };

  // The accessor at `accessor_index`, which must exist.
  const tinygltf::Accessor& accessor(int accessor_index, const std::string& field) const;
  Span span(int accessor_index, const std::string& field) const;
  // Calls `visit(i, const unsigned char* element)` for each element of the accessor.
  static void forEach(const Span& s, const std::function<void(std::size_t, const unsigned char*)>& visit);

  const tinygltf::Model& gltf_;
  std::string file_;
};

}  // namespace holo::gltf_detail
