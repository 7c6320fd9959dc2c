// The albedo of the real surfaces, estimated from the camera's colour under the panorama's
// irradiance: a Lambertian surface of albedo a under irradiance E reflects L = a E / pi, so
// a = pi L / E, with E the panorama's irradiance at the vertex's normal (reflect::IrradianceSH,
// unshadowed). Clamped to [0, max_albedo]; where E is 0 the albedo is 0.
// Units: radiance linear RGB (the camera's colour as srgbToLinear / exposure).
#pragma once

#include <vector>

#include "holo/ar/depth_surface.hpp"
#include "holo/reflect/irradiance_sh.hpp"

namespace holo::ar {

// `radiance`: CV_32FC3 linear BGR of the depth's size.
std::vector<vec3> estimateAlbedo(const DepthSurface& surface, const cv::Mat& radiance,
                                 const reflect::IrradianceSH& irradiance, float max_albedo = 0.95f);

}  // namespace holo::ar
