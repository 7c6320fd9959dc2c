#include "holo/reflect/tracer_settings.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "holo/core/error.hpp"
#include "holo/reflect/foreground_pyramid.hpp"

namespace holo::reflect {

void TracerSettings::validate() const {
  const std::string src = "tracer settings";
  if (pyramid_levels < 1 || pyramid_levels > kMaxPyramidLevels)
    throw InputError(src, "pyramid_levels", "1.." + std::to_string(kMaxPyramidLevels),
                     std::to_string(pyramid_levels));
  if (aa_samples != 1 && aa_samples != 4)
    throw InputError(src, "aa_samples", "1 or 4", std::to_string(aa_samples));
  if (!std::isfinite(max_reflection_distance) || !(max_reflection_distance > 0.0f))
    throw InputError(src, "max_reflection_distance", "a finite distance > 0 (metres)",
                     std::to_string(max_reflection_distance));
  if (!std::isfinite(ray_offset) || ray_offset < 0.0f || ray_offset > 0.1f)
    throw InputError(src, "ray_offset", "0..0.1 metres", std::to_string(ray_offset));
  if (!std::isfinite(exposure)) throw InputError(src, "exposure", "a finite number (<= 0 for automatic)");
  if (!std::isfinite(static_reuse_distance) || static_reuse_distance < 0.0f)
    throw InputError(src, "static_reuse_distance", "a finite distance >= 0 (metres)",
                     std::to_string(static_reuse_distance));
  if (static_retraces_per_frame < 0)
    throw InputError(src, "static_retraces_per_frame", "a count >= 0 (0: no budget)",
                     std::to_string(static_retraces_per_frame));
  if (!std::isfinite(static_defer_distance) || static_defer_distance < 0.0f ||
      (static_retraces_per_frame > 0 && static_defer_distance < static_reuse_distance))
    throw InputError(src, "static_defer_distance",
                     "a finite distance >= static_reuse_distance (" + std::to_string(static_reuse_distance) +
                         " metres) with a retrace budget",
                     std::to_string(static_defer_distance));
  if (!std::isfinite(evaluation.level_bias) || std::abs(evaluation.level_bias) > float(kMaxPyramidLevels))
    throw InputError(src, "level_bias", "a finite level offset within +-" + std::to_string(kMaxPyramidLevels),
                     std::to_string(evaluation.level_bias));
  if (!std::isfinite(lobe_fallback_roughness) || lobe_fallback_roughness < 0.0f)
    throw InputError(src, "lobe_fallback_roughness", "a roughness >= 0 (> 1: never)",
                     std::to_string(lobe_fallback_roughness));
  if (!std::isfinite(walk_per_pixel_roughness) || walk_per_pixel_roughness < 0.0f)
    throw InputError(src, "walk_per_pixel_roughness", "a roughness >= 0 (> 1: never)",
                     std::to_string(walk_per_pixel_roughness));
  if (edge_aa && aa_samples != 1) throw InputError(src, "edge_aa", "only with aa_samples 1", "aa_samples 4");
  if (!std::isfinite(foreground_map_roughness) || foreground_map_roughness < 0.0f)
    throw InputError(src, "foreground_map_roughness", "a roughness >= 0 (> 1: never)",
                     std::to_string(foreground_map_roughness));
  if (!std::isfinite(visitor_light_distance) || visitor_light_distance < 0.0f)
    throw InputError(src, "visitor_light_distance", "a finite distance >= 0 (metres)",
                     std::to_string(visitor_light_distance));
  if (visitor_light_map_width < 8 || visitor_light_map_width > 1024 || visitor_light_map_width % 2 != 0)
    throw InputError(src, "visitor_light_map_width", "an even number of texels in 8..1024",
                     std::to_string(visitor_light_map_width));
  if (foreground_map_width < 8 || foreground_map_width > 1024 || foreground_map_width % 2 != 0)
    throw InputError(src, "foreground_map_width", "an even number of texels in 8..1024",
                     std::to_string(foreground_map_width));
  if (rough_interreflection_grid != 1 && (rough_interreflection_grid < 2 || rough_interreflection_grid > 8 ||
                                          rough_interreflection_grid % 2 != 0))
    throw InputError(src, "rough_interreflection_grid", "1 (the mirror ray) or an even side 2..8",
                     std::to_string(rough_interreflection_grid));
  if (!std::isfinite(rough_interreflection_roughness) || rough_interreflection_roughness < 0.0f)
    throw InputError(src, "rough_interreflection_roughness", "a roughness >= 0 (> 1: never)",
                     std::to_string(rough_interreflection_roughness));
  if (rough_interreflection_mirror_bounces < 1 || rough_interreflection_mirror_bounces > 8)
    throw InputError(src, "rough_interreflection_mirror_bounces", "a count of mirror bounces 1..8",
                     std::to_string(rough_interreflection_mirror_bounces));
  {
    const int side = int(std::lround(std::sqrt(double(std::max(self_occlusion_rays, 0)))));
    if (side * side != self_occlusion_rays || side < 2 || side > 16)
      throw InputError(src, "self_occlusion_rays", "a square number 4..256",
                       std::to_string(self_occlusion_rays));
  }
  if (self_occlusion_bounces < 0 || self_occlusion_bounces > 8)
    throw InputError(src, "self_occlusion_bounces", "0..8", std::to_string(self_occlusion_bounces));
  if (!std::isfinite(self_occlusion_min) || self_occlusion_min < 0.0f || self_occlusion_min > 1.0f)
    throw InputError(src, "self_occlusion_min", "a share in [0, 1]", std::to_string(self_occlusion_min));
  if (!std::isfinite(effect_min_codes) || effect_min_codes < 0.0f)
    throw InputError(src, "effect_min_codes", "finite sRGB codes >= 0", std::to_string(effect_min_codes));
  if (refinement_sets < 1 || refinement_sets > 4096)
    throw InputError(src, "refinement_sets", "1..4096", std::to_string(refinement_sets));
  if (lobe_components < 1 || lobe_components > kMaxLobeComponents)
    throw InputError(src, "lobe_components", "1.." + std::to_string(kMaxLobeComponents),
                     std::to_string(lobe_components));
  if (refraction_depth < 0 || refraction_depth > kMaxInternalDepth)
    throw InputError(src, "refraction_depth", "0 (measured) or 1.." + std::to_string(kMaxInternalDepth),
                     std::to_string(refraction_depth));
  if (!std::isfinite(refraction_residual) || !(refraction_residual > 0.0f) || !(refraction_residual < 1.0f))
    throw InputError(src, "refraction_residual", "a share in (0, 1)", std::to_string(refraction_residual));
  if (!std::isfinite(evaluation.transmitted_roughness_scale) ||
      evaluation.transmitted_roughness_scale < 0.0f || evaluation.transmitted_roughness_scale > 4.0f)
    throw InputError(src, "transmitted_roughness_scale", "0..4",
                     std::to_string(evaluation.transmitted_roughness_scale));
  if (refraction_stride < 1 || refraction_stride > 4)
    throw InputError(src, "refraction_stride", "1..4 pixels", std::to_string(refraction_stride));
  if (refraction_branch_rays < 0 || refraction_branch_rays > 64)
    throw InputError(src, "refraction_branch_rays", "0..64 rays", std::to_string(refraction_branch_rays));
  if (!std::isfinite(refraction_branch_weight) || refraction_branch_weight < 0.0f ||
      refraction_branch_weight > 1.0f)
    throw InputError(src, "refraction_branch_weight", "a share in [0, 1]",
                     std::to_string(refraction_branch_weight));
  if (!std::isfinite(refraction_supersample_contrast) ||
      (refraction_supersample_contrast != 0.0f && !(refraction_supersample_contrast >= 1.0f)))
    throw InputError(src, "refraction_supersample_contrast", "0 (off) or a ratio >= 1",
                     std::to_string(refraction_supersample_contrast));
  if (plinth_map_resolution < 8 || plinth_map_resolution > 1024)
    throw InputError(src, "plinth_map_resolution", "8..1024 texels", std::to_string(plinth_map_resolution));
  if (plinth_shadow_rays < 1 || plinth_shadow_rays > 4096)
    throw InputError(src, "plinth_shadow_rays", "1..4096 rays", std::to_string(plinth_shadow_rays));
  if (caustic_photons < 1 || caustic_photons > 1000000000ull)
    throw InputError(src, "caustic_photons", "1..1e9 photons", std::to_string(caustic_photons));
  if (caustic_resolution < 8 || caustic_resolution > 2048)
    throw InputError(src, "caustic_resolution", "8..2048 cells", std::to_string(caustic_resolution));
  grid.validate(src + " grid");
}

}  // namespace holo::reflect
