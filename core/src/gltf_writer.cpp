// saveGltf and encodeGlb (gltf_io.hpp): a holo::Model as one self-contained glTF 2.0 file. Every
// mesh becomes one node with one triangle primitive (FLOAT attributes, UNSIGNED_INT indices),
// every texture a PNG in the binary buffer with its sampler, and every material property that
// differs from glTF's default the matching core field or extension.
#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "gltf_extensions.hpp"
#include "gltf_parse.hpp"
#include "gltf_tinygltf.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/gltf_io.hpp"

namespace holo {

namespace fs = std::filesystem;

namespace {

using gltf_detail::kClearcoat;
using gltf_detail::kEmissiveStrength;
using gltf_detail::kIor;
using gltf_detail::kSpecular;
using gltf_detail::kTextureTransform;
using gltf_detail::kTransmission;
using gltf_detail::kVolume;

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

// Each texture as a PNG image in buffer 0, with its own sampler and a glTF texture of the same index.
void writeTextures(tinygltf::Model& g, const Model& model) {
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
}

// KHR_materials_specular, _clearcoat, _transmission, _volume and _ior, each where it differs
// from the extension's defaults.
void writeLayerExtensions(const Material& m, TextureWriter& textures, tinygltf::Material& mat) {
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
}

// The core properties, the emission above 1 as KHR_materials_emissive_strength, then the layers.
tinygltf::Material writeMaterial(const Material& m, TextureWriter& textures) {
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
  writeLayerExtensions(m, textures, mat);
  return mat;
}

// One attribute of `n` elements as a FLOAT accessor of `type` over its own buffer view.
template <class T>
int appendAttribute(tinygltf::Model& g, const std::vector<T>& values, std::size_t n, int type) {
  return appendAccessor(g, appendView(g, values.data(), n * sizeof(T), TINYGLTF_TARGET_ARRAY_BUFFER),
                        TINYGLTF_COMPONENT_TYPE_FLOAT, type, n);
}

// The mesh as a glTF mesh of one primitive, instanced by a new root node of `scene`.
void writeMesh(tinygltf::Model& g, const TriangleMesh& mesh, tinygltf::Scene& scene) {
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.material = mesh.material;
  const std::size_t n = mesh.positions.size();
  const int pos = appendAttribute(g, mesh.positions, n, TINYGLTF_TYPE_VEC3);
  const Bounds3 b = mesh.bounds();
  if (!b.empty()) {
    g.accessors[static_cast<std::size_t>(pos)].minValues = {b.lo.x, b.lo.y, b.lo.z};
    g.accessors[static_cast<std::size_t>(pos)].maxValues = {b.hi.x, b.hi.y, b.hi.z};
  }
  prim.attributes["POSITION"] = pos;
  if (mesh.normals.size() == n)
    prim.attributes["NORMAL"] = appendAttribute(g, mesh.normals, n, TINYGLTF_TYPE_VEC3);
  if (mesh.uvs.size() == n)
    prim.attributes["TEXCOORD_0"] = appendAttribute(g, mesh.uvs, n, TINYGLTF_TYPE_VEC2);
  if (mesh.uvs1.size() == n)
    prim.attributes["TEXCOORD_1"] = appendAttribute(g, mesh.uvs1, n, TINYGLTF_TYPE_VEC2);
  if (mesh.tangents.size() == n)
    prim.attributes["TANGENT"] = appendAttribute(g, mesh.tangents, n, TINYGLTF_TYPE_VEC4);
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

tinygltf::Model toGltf(const Model& model) {
  tinygltf::Model g;
  g.asset.version = "2.0";
  g.asset.generator = "holopyramid";
  g.buffers.emplace_back();
  writeTextures(g, model);
  std::set<std::string> extensions;
  TextureWriter textures;
  for (const auto& m : model.materials) {
    g.materials.push_back(writeMaterial(m, textures));
    for (const auto& [name, value] : g.materials.back().extensions) extensions.insert(name);
  }
  if (textures.used()) extensions.insert(kTextureTransform);
  tinygltf::Scene scene;
  for (const auto& mesh : model.meshes) writeMesh(g, mesh, scene);
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
  const std::string ext = gltf_detail::formatExtension(path);
  if (ext != ".gltf" && ext != ".glb") throw InputError(path.string(), "", "a .gltf or .glb file name", ext);
  writeFileAtomically(path, serialize(model, ext == ".glb"));
}

}  // namespace holo
