// The public reading entry points of gltf_io.hpp: loadGltf, loadGlbFromMemory and the inventory
// inspectGltf. Parsing is gltf_parse.hpp's, the flattening into a Model gltf_scene.hpp's.
#include "holo/core/gltf_io.hpp"

#include <algorithm>
#include <functional>
#include <utility>

#include "gltf_materials.hpp"
#include "gltf_parse.hpp"
#include "gltf_scene.hpp"

namespace holo {

namespace fs = std::filesystem;

namespace {

// Every extension readMaterials reads has its factors rendered by both renderers; their textures
// are listed per slot.
GltfSupport extensionSupport(const std::string& extension) {
  return gltf_detail::readsExtension(extension) ? GltfSupport::Rendered : GltfSupport::Ignored;
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
  return gltf_detail::flattenScene(gltf_detail::parseGltfFile(path), path.string());
}

Model loadGlbFromMemory(const std::vector<std::uint8_t>& glb, const std::string& origin) {
  return gltf_detail::flattenScene(gltf_detail::parseGlb(glb, origin), origin);
}

GltfInventory inspectGltf(const fs::path& path) {
  const tinygltf::Model gltf = gltf_detail::parseGltfFile(path);
  GltfInventory out;
  out.model = gltf_detail::flattenScene(gltf, path.string());
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

}  // namespace holo
