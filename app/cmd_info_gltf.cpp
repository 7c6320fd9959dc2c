#include <iostream>

#include "holo/core/gltf_io.hpp"
#include "info_gltf.hpp"

namespace holo::app {

int describeGltf(const std::filesystem::path& path) {
  const Model model = loadGltf(path);
  const Bounds3 b = model.bounds();
  std::cout << "file: " << path.string() << "\n"
            << "type: glTF model\n"
            << "meshes: " << model.meshes.size() << "\n"
            << "triangles: " << model.triangleCount() << "\n"
            << "textures: " << model.textures.size() << "\n"
            << "bounds min (m): " << b.lo.x << " " << b.lo.y << " " << b.lo.z << "\n"
            << "bounds max (m): " << b.hi.x << " " << b.hi.y << " " << b.hi.z << "\n"
            << "materials: " << model.materials.size() << "\n";
  for (const auto& m : model.materials)
    std::cout << "  " << (m.name.empty() ? "(unnamed)" : m.name) << ": base colour " << m.base_color.r << " "
              << m.base_color.g << " " << m.base_color.b << ", metallic " << m.metallic << ", roughness "
              << m.roughness << (m.base_color_texture >= 0 ? ", base colour texture" : "")
              << (m.metallic_roughness_texture >= 0 ? ", metallic-roughness texture" : "") << "\n";
  return 0;
}

}  // namespace holo::app
