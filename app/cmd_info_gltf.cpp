#include <iostream>

#include "holo/core/gltf_io.hpp"
#include "info_gltf.hpp"

namespace holo::app {

namespace {

void printFeatures(const char* title, const std::vector<GltfFeature>& features) {
  std::cout << title << ": " << features.size() << "\n";
  for (const auto& f : features) {
    std::cout << "  " << f.name << ": " << describe(f.support);
    if (f.required) std::cout << ", required";
    if (f.materials > 0)
      std::cout << " (" << f.materials << (f.materials == 1 ? " material)" : " materials)");
    std::cout << "\n";
  }
}

}  // namespace

int describeGltf(const std::filesystem::path& path) {
  const GltfInventory inventory = inspectGltf(path);
  const Model& model = inventory.model;
  const Bounds3 b = model.bounds();
  std::cout << "file: " << path.string() << "\n"
            << "type: glTF model\n"
            << "meshes: " << model.meshes.size() << "\n"
            << "triangles: " << model.triangleCount() << "\n"
            << "textures: " << model.textures.size() << "\n"
            << "bounds min (m): " << b.lo.x << " " << b.lo.y << " " << b.lo.z << "\n"
            << "bounds max (m): " << b.hi.x << " " << b.hi.y << " " << b.hi.z << "\n"
            << "materials: " << model.materials.size() << "\n";
  for (const auto& m : model.materials) {
    std::cout << "  " << (m.name.empty() ? "(unnamed)" : m.name) << ": base colour " << m.base_color.r << " "
              << m.base_color.g << " " << m.base_color.b << ", metallic " << m.metallic << ", roughness "
              << m.roughness;
    if (m.transmissive())
      std::cout << ", transmission " << m.transmission << ", ior " << m.ior << ", thickness " << m.thickness;
    if (m.clearcoat > 0.0f)
      std::cout << ", clearcoat " << m.clearcoat << " (roughness " << m.clearcoat_roughness << ")";
    std::cout << "\n";
  }
  printFeatures("extensions", inventory.extensions);
  printFeatures("texture slots", inventory.texture_slots);
  printFeatures("material properties", inventory.properties);
  return 0;
}

}  // namespace holo::app
