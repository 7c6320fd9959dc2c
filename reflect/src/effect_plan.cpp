#include "holo/reflect/effect_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace holo::reflect {
namespace {

// Distance between two boxes (0 when they overlap).
float boxDistance(const Bounds3& a, const Bounds3& b) {
  const vec3 gap = glm::max(glm::max(a.lo - b.hi, b.lo - a.hi), vec3(0.0f));
  return glm::length(gap);
}

}  // namespace

const char* passName(Pass pass) {
  switch (pass) {
    case Pass::VoxelGrid:
      return "VoxelGrid";
    case Pass::Pyramids:
      return "Pyramids";
    case Pass::RoughForegroundMap:
      return "RoughForegroundMap";
    case Pass::HitPoints:
      return "HitPoints";
    case Pass::SelfOcclusion:
      return "SelfOcclusion";
    case Pass::StaticReflections:
      return "StaticReflections";
    case Pass::AxisAlignedFilter:
      return "AxisAlignedFilter";
    case Pass::ForegroundWalk:
      return "ForegroundWalk";
    case Pass::Composition:
      return "Composition";
    case Pass::VisitorLight:
      return "VisitorLight";
    case Pass::ToneMap:
      return "ToneMap";
    case Pass::Refraction:
      return "Refraction";
    case Pass::RefractedForeground:
      return "RefractedForeground";
    case Pass::Clearcoat:
      return "Clearcoat";
    case Pass::ProgressiveRefinement:
      return "ProgressiveRefinement";
    case Pass::Caustics:
      return "Caustics";
    case Pass::Plinth:
      return "Plinth";
  }
  return "?";
}

bool EffectPlan::has(Pass pass) const {
  return std::find(passes.begin(), passes.end(), pass) != passes.end();
}

std::string EffectPlan::describe() const {
  std::string s;
  for (Pass p : passes) {
    if (!s.empty()) s.push_back(',');
    s.append(passName(p));
  }
  s.append(" (");
  s.append(foreground_reason);
  if (!material_reason.empty()) {
    s.append("; ");
    s.append(material_reason);
  }
  if (!visitor_light_reason.empty()) {
    s.append("; ");
    s.append(visitor_light_reason);
  }
  if (!plinth_reason.empty()) {
    s.append("; ");
    s.append(plinth_reason);
  }
  s.push_back(')');
  return s;
}

EffectPlan planEffects(const EffectInputs& in) {
  EffectPlan plan;
  if (in.relic_empty) {
    plan.foreground_reason = "no relic";
    plan.material_reason = "no relic";
    plan.visitor_light_reason = "no relic";
    plan.passes = {Pass::ToneMap};
    return plan;
  }
  if (!in.foreground_enabled)
    plan.foreground_reason = "foreground effect off";
  else if (in.foreground_points == 0 || in.foreground_bounds.empty())
    plan.foreground_reason = "no foreground points";
  else if (in.cameras == 0)
    plan.foreground_reason = "no foreground cameras";
  else if (!in.relic_glossy && !in.relic_transmissive)
    plan.foreground_reason = "no glossy relic material";
  else if (!(boxDistance(in.relic_bounds, in.foreground_bounds) <= in.max_reflection_distance))
    plan.foreground_reason = "foreground beyond the reflection distance";
  else if (in.relic_glossy)
    plan.foreground_reason = "foreground near a glossy relic";
  else
    plan.foreground_reason = "foreground near a transmissive relic";
  const bool foreground = plan.foreground_reason == "foreground near a glossy relic" ||
                          plan.foreground_reason == "foreground near a transmissive relic";
  if (in.relic_transmissive) {
    plan.internal_depth = std::max(in.internal_depth, 1);
    char residual[32];
    std::snprintf(residual, sizeof residual, "%.2g%%", double(in.internal_residual) * 100.0);
    plan.material_reason =
        "transmissive relic material, internal depth " + std::to_string(plan.internal_depth) + " (" +
        (in.internal_depth_source.empty() ? "set" : in.internal_depth_source) + ", " + residual + " left)";
  } else {
    plan.material_reason = "opaque relic";
  }
  plan.material_reason += in.relic_clearcoat ? ", clearcoat" : ", no clearcoat";
  if (!in.self_occlusion_reason.empty()) plan.material_reason += ", " + in.self_occlusion_reason;
  if (!in.progressive_refinement_reason.empty())
    plan.material_reason += ", " + in.progressive_refinement_reason;
  const bool visitor_present = in.foreground_points > 0 && !in.foreground_bounds.empty();
  const bool visitor_near = in.visitor_light_enabled && in.relic_lit_diffusely && visitor_present &&
                            in.visitor_within_light_distance;
  const bool visitor_light = visitor_near && in.visitor_light_codes >= in.effect_min_codes;
  char codes[64] = "";
  if (std::isfinite(in.visitor_light_codes))
    std::snprintf(codes, sizeof codes, " (at most %.2g sRGB codes)", double(in.visitor_light_codes));
  plan.visitor_light_reason =
      !in.visitor_light_enabled ? "visitors' light off"
      : !in.relic_lit_diffusely ? "no diffuse or wide-lobed relic material: no visitors' light"
      : !visitor_present        ? "no visitor to light the relic"
      : !visitor_near           ? "no visitor near enough to light the relic"
      : !visitor_light          ? std::string("visitors' light not shown") + codes
                                : std::string("visitors near the relic's diffuse light") + codes;
  if (!in.lobe_filter_reason.empty()) plan.material_reason += ", " + in.lobe_filter_reason;
  plan.interreflection = in.interreflection && !in.relic_convex;
  plan.material_reason += !in.interreflection ? ", interreflection off"
                          : in.relic_convex   ? ", convex relic: no interreflection"
                                              : ", interreflection where the relic can see itself";
  plan.sun_light = in.sun_light_enabled && in.panorama_sun && in.relic_lit_diffusely;
  plan.material_reason += !in.sun_light_enabled     ? ", sun light off"
                          : !in.panorama_sun        ? ", " + in.panorama_sun_description + ": no sun light"
                          : !in.relic_lit_diffusely ? ", nothing diffuse: no sun light"
                                                    : ", sun light (" + in.panorama_sun_description + ")";
  if (foreground) plan.passes = {Pass::VoxelGrid, Pass::Pyramids};
  if (!foreground && visitor_light) plan.passes = {Pass::VoxelGrid};
  if (foreground && in.relic_rough) plan.passes.push_back(Pass::RoughForegroundMap);
  plan.passes.push_back(Pass::HitPoints);
  if (in.self_occlusion) plan.passes.push_back(Pass::SelfOcclusion);
  plan.passes.push_back(Pass::StaticReflections);
  if (in.lobe_filter && plan.interreflection) plan.passes.push_back(Pass::AxisAlignedFilter);
  if (in.relic_transmissive) plan.passes.push_back(Pass::Refraction);
  if (in.relic_clearcoat) plan.passes.push_back(Pass::Clearcoat);
  if (in.progressive_refinement && plan.interreflection && !in.relic_transmissive && !in.relic_clearcoat)
    plan.passes.push_back(Pass::ProgressiveRefinement);
  if (foreground) {
    plan.passes.push_back(Pass::ForegroundWalk);
    if (in.relic_transmissive && in.refracted_foreground) plan.passes.push_back(Pass::RefractedForeground);
    plan.passes.push_back(Pass::Composition);
  }
  if (visitor_light) plan.passes.push_back(Pass::VisitorLight);
  const bool caustics = in.plinth && in.plinth_caustic && in.relic_transmissive;
  plan.plinth_reason = !in.plinth               ? "no plinth"
                       : !in.relic_transmissive ? "plinth under an opaque relic: no caustic"
                       : !in.plinth_caustic     ? "plinth, caustic off"
                                                : "plinth under a transmissive relic: caustic";
  if (caustics) plan.passes.push_back(Pass::Caustics);
  if (in.plinth) plan.passes.push_back(Pass::Plinth);
  plan.passes.push_back(Pass::ToneMap);
  return plan;
}

}  // namespace holo::reflect
