// Triangle meshes and glTF 2.0 metallic-roughness materials with the material extensions a
// museum's relics use, as loaded from glTF or made by the simulator. Positions in metres, +Y up.
// Invariants: normals, tangents, uvs and uvs1 (each when present) have one entry per position;
// every triangle index < positions.size(); every Material factor is finite, and those glTF
// bounds to [0,1] lie in [0,1].
#pragma once

#include <limits>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "holo/core/math.hpp"
#include "holo/core/texture.hpp"

namespace holo {

// A material's use of a texture (glTF textureInfo with KHR_texture_transform). The uv a slot
// samples is transform(uv of set tex_coord): scale, then rotate by `rotation` radians
// (counter-clockwise in uv), then offset, as the extension defines.
struct TextureRef {
  int index = -1;      // into Model::textures; -1: the slot is unused
  int tex_coord = 0;   // 0: TriangleMesh::uvs (TEXCOORD_0), 1: TriangleMesh::uvs1 (TEXCOORD_1)
  vec2 offset{0.0f};   // uv units
  float rotation = 0;  // radians
  vec2 scale{1.0f};

  bool used() const { return index >= 0; }
  vec2 transform(vec2 uv) const;
};

enum class AlphaMode { Opaque, Mask, Blend };

// Every factor multiplies its texture (an unused texture reads 1). Colours are linear RGB;
// textures marked sRGB are decoded to linear before multiplying.
struct Material {
  std::string name;
  vec3 base_colour{0.8f};  // baseColorFactor RGB; base_color_texture is sRGB (alpha in A)
  float alpha = 1.0f;      // baseColorFactor A, [0,1]; times the base colour texture's alpha
  float metallic = 0.0f;   // [0,1]; metallic_roughness_texture B
  float roughness = 1.0f;  // [0,1] perceptual; GGX alpha = roughness^2; 0 = mirror; texture G
  vec3 emission{0.0f};     // linear radiance emitted: emissiveFactor x emissive_strength (>= 0)
  TextureRef base_colour_texture;
  TextureRef metallic_roughness_texture;  // linear: G roughness, B metallic
  TextureRef emissive_texture;            // sRGB, multiplies `emission`

  TextureRef normal_texture;        // tangent-space normal map (needs TriangleMesh::tangents)
  float normal_scale = 1.0f;        // scales the map's X and Y
  TextureRef occlusion_texture;     // linear R: ambient occlusion of indirect (IBL) light only
  float occlusion_strength = 1.0f;  // [0,1]: 1 + strength * (R - 1)

  AlphaMode alpha_mode = AlphaMode::Opaque;
  float alpha_cutoff = 0.5f;  // Mask: alpha >= cutoff is opaque, below is absent
  bool double_sided = false;  // false: back faces are culled

  // KHR_materials_specular: dielectric F0 = ((ior-1)/(ior+1))^2 x specular_color, weighted by
  // specular.
  float specular = 1.0f;       // [0,1]; specular_texture A
  vec3 specular_colour{1.0f};  // >= 0 (may exceed 1); specular_color_texture sRGB
  TextureRef specular_texture;
  TextureRef specular_colour_texture;

  // KHR_materials_clearcoat: a smooth dielectric layer (IOR 1.5) over the base.
  float clearcoat = 0.0f;            // [0,1] layer weight; clearcoat_texture R
  float clearcoat_roughness = 0.0f;  // [0,1] perceptual; clearcoat_roughness_texture G
  TextureRef clearcoat_texture;
  TextureRef clearcoat_roughness_texture;
  TextureRef clearcoat_normal_texture;  // the layer's own normal map
  float clearcoat_normal_scale = 1.0f;

  // KHR_materials_transmission: fraction of the dielectric base's light that is transmitted.
  float transmission = 0.0f;  // [0,1]; transmission_texture R
  TextureRef transmission_texture;

  // KHR_materials_volume: thickness 0 means thin-walled (light passes straight through).
  float thickness = 0.0f;  // metres in the mesh's own frame, >= 0; thickness_texture G
  TextureRef thickness_texture;
  vec3 attenuation_colour{1.0f};  // [0,1] colour white light has after attenuation_distance
  float attenuation_distance = std::numeric_limits<float>::infinity();  // metres, > 0; inf: clear

  float ior = 1.5f;  // KHR_materials_ior, >= 1

  bool transmissive() const { return transmission > 0.0f; }
};

struct TriangleMesh {
  std::string name;
  std::vector<vec3> positions;
  std::vector<vec3> normals;   // per vertex, unit length; empty until computed
  std::vector<vec4> tangents;  // per vertex: xyz unit, orthogonal to the normal; w = +-1
                               // handedness (bitangent = w cross(normal, xyz)); may be empty
  std::vector<vec2> uvs;       // TEXCOORD_0 per vertex; may be empty
  std::vector<vec2> uvs1;      // TEXCOORD_1 per vertex; may be empty
  std::vector<uvec3> triangles;
  int material = 0;  // index into Model::materials

  Bounds3 bounds() const;
  // Area-weighted vertex normals; degenerate triangles contribute nothing and a vertex that only
  // touches degenerate triangles gets +Y.
  void computeNormals();
  // MikkTSpace-style tangents from the uv set `tex_coord` (0: uvs, 1: uvs1); needs normals.
  // Without that uv set every vertex gets a finite frame orthogonal to its normal.
  void computeTangents(int tex_coord = 0);
  // Positions by T, normals by its inverse transpose, tangents by T (handedness flips with a
  // mirroring T, as the bitangent's cross product does).
  void transform(const mat4& T);
};

struct Model {
  std::vector<TriangleMesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;  // one per glTF texture a material uses

  Bounds3 bounds() const;
  std::size_t triangleCount() const;
  void transform(const mat4& T);
};

}  // namespace holo
