#include "holo/ar/albedo_estimate.hpp"

#include <glm/gtc/constants.hpp>

namespace holo::ar {

std::vector<vec3> estimateAlbedo(const DepthSurface& surface, const cv::Mat& radiance,
                                 const reflect::IrradianceSH& irradiance, float max_albedo) {
  std::vector<vec3> albedo(surface.mesh.positions.size(), vec3(0.0f));
  for (std::size_t i = 0; i < albedo.size(); ++i) {
    const vec3 E = irradiance.irradiance(surface.mesh.normals[i]);
    const vec3 L = rgbAt(radiance, surface.pixels[i].x, surface.pixels[i].y);
    for (int c = 0; c < 3; ++c)
      albedo[i][c] = E[c] > 1e-6f ? std::clamp(glm::pi<float>() * L[c] / E[c], 0.0f, max_albedo) : 0.0f;
  }
  return albedo;
}

}  // namespace holo::ar
