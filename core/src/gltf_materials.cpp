#include "gltf_materials.hpp"

#include <cmath>
#include <cstring>

#include "gltf_extensions.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/core/stats.hpp"

namespace holo::gltf_detail {

namespace {

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
                 TextureTable& textures)
      : file_(file), textures_(textures) {
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
    ref.index = textures_.index(index, encodingOf(field));
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
    // Appended piecewise: GCC 12 misreads "[" + std::to_string(k) here as an overlapping copy
    // (-Wrestrict) once this class is inlined.
    std::string f = where_ + "." + field + "." + key;
    if (k >= 0) f.append("[").append(std::to_string(k)).append("]");
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
  TextureTable& textures_;
  std::string where_;
};

// The extension object `name` of material `m`, or a null value when the material has none.
const tinygltf::Value& extensionOf(const tinygltf::Material& m, const char* name) {
  static const tinygltf::Value none;
  const auto it = m.extensions.find(name);
  return it == m.extensions.end() ? none : it->second;
}

// The glTF 2.0 core properties (with KHR_materials_emissive_strength, which scales the emission).
void readCoreProperties(const tinygltf::Material& m, const MaterialReader& r, Material& mat) {
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
      r.number(extensionOf(m, kEmissiveStrength), "emissiveStrength", 1.0f,
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
}

// KHR_materials_specular, _clearcoat, _transmission, _volume and _ior.
void readLayerExtensions(const tinygltf::Material& m, const MaterialReader& r, Material& mat) {
  const std::string ext = "extensions.";
  const tinygltf::Value& spec = extensionOf(m, kSpecular);
  const std::string spec_field = ext + kSpecular;
  mat.specular = r.number(spec, "specularFactor", 1.0f, spec_field + ".specularFactor", true);
  mat.specular_colour =
      r.colour(spec, "specularColorFactor", vec3(1.0f), spec_field + ".specularColorFactor", false);
  mat.specular_texture = r.texture(spec, "specularTexture", spec_field);
  mat.specular_colour_texture = r.texture(spec, "specularColorTexture", spec_field);

  const tinygltf::Value& coat = extensionOf(m, kClearcoat);
  const std::string coat_field = ext + kClearcoat;
  mat.clearcoat = r.number(coat, "clearcoatFactor", 0.0f, coat_field + ".clearcoatFactor", true);
  mat.clearcoat_roughness =
      r.number(coat, "clearcoatRoughnessFactor", 0.0f, coat_field + ".clearcoatRoughnessFactor", true);
  mat.clearcoat_texture = r.texture(coat, "clearcoatTexture", coat_field);
  mat.clearcoat_roughness_texture = r.texture(coat, "clearcoatRoughnessTexture", coat_field);
  mat.clearcoat_normal_texture =
      r.texture(coat, "clearcoatNormalTexture", coat_field, &mat.clearcoat_normal_scale);

  const tinygltf::Value& transmission = extensionOf(m, kTransmission);
  const std::string transmission_field = ext + kTransmission;
  mat.transmission =
      r.number(transmission, "transmissionFactor", 0.0f, transmission_field + ".transmissionFactor", true);
  mat.transmission_texture = r.texture(transmission, "transmissionTexture", transmission_field);

  const tinygltf::Value& volume = extensionOf(m, kVolume);
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

  const tinygltf::Value& ior = extensionOf(m, kIor);
  mat.ior = r.number(ior, "ior", 1.5f, ext + kIor + ".ior", false);
  if (mat.ior < 1.0f)
    throw InputError(r.file(), r.where() + "." + ext + kIor + ".ior", "an index of refraction >= 1",
                     std::to_string(mat.ior));
}

}  // namespace

bool readsExtension(const std::string& name) {
  for (const char* known :
       {kEmissiveStrength, kTextureTransform, kSpecular, kClearcoat, kTransmission, kVolume, kIor})
    if (name == known) return true;
  return false;
}

std::vector<Material> readMaterials(const tinygltf::Model& gltf, const std::string& file,
                                    TextureTable& textures) {
  std::vector<Material> out;
  for (std::size_t i = 0; i < gltf.materials.size(); ++i) {
    const MaterialReader reader(gltf, file, i, textures);
    const auto& m = gltf.materials[i];
    Material mat;
    mat.name = m.name;
    readCoreProperties(m, reader, mat);
    readLayerExtensions(m, reader, mat);
    out.push_back(std::move(mat));
  }
  return out;
}

}  // namespace holo::gltf_detail
