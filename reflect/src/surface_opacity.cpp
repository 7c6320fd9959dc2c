#include "surface_opacity.hpp"

#include <algorithm>

#include "mesh_attributes.hpp"

namespace holo::reflect {

bool needsOpacity(const Material& m) {
  return m.alpha_mode != AlphaMode::Opaque || (!m.double_sided && !m.transmissive());
}

float surfaceOpacity(const Model& model, std::size_t mesh_index, const Ray& ray, const RayHit& hit) {
  const TriangleMesh& mesh = model.meshes[mesh_index];
  const Material& m = meshMaterial(model, mesh_index);
  const Corner c = cornerOf(mesh, hit);
  if (!m.double_sided && !m.transmissive() && glm::dot(outwardGeometricNormal(mesh, c), ray.direction) > 0.0f)
    return 0.0f;
  switch (m.alpha_mode) {
    case AlphaMode::Opaque:
      return 1.0f;
    case AlphaMode::Mask:
      return materialAlpha(model, mesh, m, c) >= m.alpha_cutoff ? 1.0f : 0.0f;
    case AlphaMode::Blend:
      return std::clamp(materialAlpha(model, mesh, m, c), 0.0f, 1.0f);
  }
  return 1.0f;
}

}  // namespace holo::reflect
