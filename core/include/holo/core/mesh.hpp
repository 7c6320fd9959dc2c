// Triangle meshes and glTF-style metallic-roughness materials, as loaded from glTF or made by
// the simulator. Positions in metres, +Y up. Invariants: normals (when present) and uvs (when
// present) have one entry per position; every triangle index < positions.size().
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "holo/core/math.hpp"

namespace holo {

struct Material {
  std::string name;
  vec3 base_color{0.8f};                // linear RGB factor (glTF baseColorFactor)
  float metallic = 0.0f;                // [0,1]
  float roughness = 1.0f;               // [0,1] perceptual roughness; GGX alpha = roughness^2; 0 = mirror
  vec3 emission{0.0f};                  // linear radiance emitted (glTF emissiveFactor x strength)
  int base_color_texture = -1;          // index into Model::textures, sRGB-encoded
  int metallic_roughness_texture = -1;  // index into Model::textures, linear (G rough, B metal)
};

struct TriangleMesh {
  std::string name;
  std::vector<vec3> positions;
  std::vector<vec3> normals;  // per vertex, unit length; empty until computed
  std::vector<vec2> uvs;      // per vertex; may be empty
  std::vector<uvec3> triangles;
  int material = 0;  // index into Model::materials

  Bounds3 bounds() const;
  // Area-weighted vertex normals; degenerate triangles contribute nothing and a vertex that only
  // touches degenerate triangles gets +Y.
  void computeNormals();
  void transform(const mat4& T);  // positions by T, normals by its inverse transpose
};

struct Model {
  std::vector<TriangleMesh> meshes;
  std::vector<Material> materials;
  std::vector<cv::Mat> textures;  // CV_8UC3 BGR or CV_8UC4 BGRA, as decoded

  Bounds3 bounds() const;
  std::size_t triangleCount() const;
  void transform(const mat4& T);
};

}  // namespace holo
