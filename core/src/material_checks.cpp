#include "holo/core/material_checks.hpp"

#include <algorithm>
#include <sstream>

#include "holo/core/ray_scene.hpp"

namespace holo {
namespace {

// The median distance from a face, inwards along its normal, to the next face of the same meshes:
// how thick the walls are (0 when no ray finds a wall: open sheets). Up to kProbes faces, spread
// evenly over the triangles.
float medianWallThickness(const Model& model, std::size_t material) {
  constexpr std::size_t kProbes = 256;
  RayScene scene;
  std::vector<const TriangleMesh*> meshes;
  for (const TriangleMesh& mesh : model.meshes)
    if (std::size_t(mesh.material) == material) {
      scene.addMesh(mesh);
      meshes.push_back(&mesh);
    }
  scene.commit();
  std::size_t triangles = 0;
  for (const TriangleMesh* mesh : meshes) triangles += mesh->triangles.size();
  if (triangles == 0) return 0.0f;
  const std::size_t step = std::max<std::size_t>(1, triangles / kProbes);
  std::vector<float> walls;
  std::size_t index = 0;
  for (const TriangleMesh* mesh : meshes)
    for (const uvec3& t : mesh->triangles) {
      if (index++ % step != 0) continue;
      const vec3 a = mesh->positions[t.x], b = mesh->positions[t.y], c = mesh->positions[t.z];
      const vec3 n = glm::cross(b - a, c - a);
      const float area2 = glm::length(n);
      if (!(area2 > 0.0f)) continue;
      const Ray ray{(a + b + c) / 3.0f, -n / area2};
      const RayHit hit = scene.intersect(ray, 1e-6f);
      if (hit.hit()) walls.push_back(hit.t);
    }
  if (walls.empty()) return 0.0f;
  std::nth_element(walls.begin(), walls.begin() + std::ptrdiff_t(walls.size() / 2), walls.end());
  return walls[walls.size() / 2];
}

}  // namespace

std::vector<MaterialWarning> checkMaterials(const Model& model) {
  std::vector<MaterialWarning> warnings;
  for (std::size_t i = 0; i < model.materials.size(); ++i) {
    const Material& m = model.materials[i];
    const auto meshes =
        std::count_if(model.meshes.begin(), model.meshes.end(),
                      [&](const TriangleMesh& mesh) { return std::size_t(mesh.material) == i; });
    if (meshes == 0) continue;
    const std::string name =
        "material " + std::to_string(i) + (m.name.empty() ? "" : " (\"" + m.name + "\")");
    if (m.alpha_mode == AlphaMode::Blend && !(m.alpha > 0.0f)) {
      std::ostringstream line;
      line << name << ": alphaMode BLEND with baseColorFactor alpha 0 makes its " << meshes
           << (meshes == 1 ? " mesh" : " meshes") << " invisible";
      warnings.push_back({i, line.str()});
    }
    if (m.transmissive() && m.thickness > 0.0f) {
      const float wall = medianWallThickness(model, i);
      if (wall > 0.0f && (m.thickness > kThicknessFar * wall || m.thickness * kThicknessFar < wall)) {
        std::ostringstream line;
        line << name << ": KHR_materials_volume thickness " << m.thickness
             << " is far from its meshes' walls (median " << wall
             << " across); rendered through the meshes' own walls, where a viewer that refracts by the "
                "thickness shows it otherwise";
        warnings.push_back({i, line.str()});
      }
    }
  }
  return warnings;
}

}  // namespace holo
