// The efficient reflection tracer's frame renderer (paper steps 3-5): per frame it bins the
// foreground cloud into the voxel grid and builds each camera's Kawase pyramids, then per face
// view traces hit points on the relic, shades the static reflection psi_s from the prefiltered
// IBL (one bounce further where the mirror ray meets the relic itself), walks each reflected ray
// through the voxel grid for the foreground radiance psi_d and weight w (the camera that saw the
// voxel, read at the pyramid levels of the hit's GGX lobe and the ray's travel distance; the
// roughest materials read the visitors prefiltered around the relic instead), composes
// psi_f = psi_d w + psi_s (1 - w) in HDR (specular part; the diffuse irradiance is added to
// both), and tone-maps to sRGB. Which passes run comes from the effect plan (effect_plan.hpp);
// every pass is timed. The relic's self-occlusion (relic_visibility.hpp) is built with the
// renderer, for a diffuse relic that is not convex and shadows itself enough to show. Visitors near
// a relic with diffuse or very rough surfaces shadow and light them (visitor_light.hpp), built per
// frame from the voxel grid and added to each view after the composition. The passes live in
// reflect/src: static_shading, foreground_walk (with its camera choice and near-miss march), compose_pass,
// and tone_map.hpp's toneMapCovered. What it takes and returns has its own headers: tracer_settings.hpp,
// foreground_camera_image.hpp, frame_result.hpp.
//
// The relic and the hall do not move, only the eyes: per view slot (the index in `views`) the
// renderer keeps the hit points, their static shading and the static image (psi_s + diffuse, and
// its tone-mapped form when the exposure is fixed), and reuses them while that view's camera stays
// within static_reuse_distance of the one they were traced from (the result is then rendered from
// the cached camera). With a budget of static_retraces_per_frame, only that many views whose eye
// moved beyond it trace again in one frame, the others a frame or more later (their eye within
// static_defer_distance), so several eyes moving at once do not make one frame several times
// longer. A frame then costs only the foreground: the walk over the cached hit points and the
// composition of the pixels some foreground reached, written over a copy of the static image. The
// views are rendered in parallel, each into its own slot; a view's images do not depend on the
// others (the same as rendering it alone). While the view and the foreground stay still, the rough
// interreflection accumulates one more sample set a frame (ProgressiveRefinement,
// reflect/src/progressive_accumulation.hpp). With a plinth configured (TracerSettings::plinth)
// every view shows it under the relic, lit by the hall and shadowed by the relic, with a
// transmissive relic's caustic on it (caustic_tracer.hpp), its light recomputed only when the
// panorama or the relic's turn changes (on the frame thread).
// Units: metres, linear radiance; images CV_32FC3 linear BGR (HDR) and CV_8UC3 sRGB BGR.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/core/math.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"
#include "holo/reflect/caustic_tracer.hpp"
#include "holo/reflect/effect_plan.hpp"
#include "holo/reflect/foreground_camera_image.hpp"
#include "holo/reflect/foreground_pyramid.hpp"
#include "holo/reflect/frame_result.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/relic_visibility.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/rough_foreground_map.hpp"
#include "holo/reflect/tracer_settings.hpp"
#include "holo/reflect/visitor_light.hpp"
#include "holo/reflect/voxel_grid.hpp"

namespace holo::reflect {

class LobeEffectGate;
class PlinthLight;
class WideLobeCache;

class FrameRenderer {
 public:
  // The scene and IBL must outlive the renderer. Throws InputError on invalid settings.
  FrameRenderer(const RenderScene& scene, const PrefilteredIbl& ibl, TracerSettings settings = {});
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // The plan before the visitors' voxels are binned: VisitorLight wherever one is near enough
  // (render() also leaves it off where their largest displayed change is below
  // effect_min_codes). AxisAlignedFilter and ProgressiveRefinement at the exposure fixed in the
  // settings or, when automatic, the largest a view chose in the last frame (before any frame:
  // on, as nothing is known); render() also leaves the filter off where its own displayed change,
  // measured in the views' last static passes with it, was below effect_min_codes, and a view's
  // refinement where what its accumulation changed, measured where it last ran, was
  // (lobe_effect_gate.hpp).
  EffectPlan plan(const depthfilter::ForegroundCloud& cloud,
                  const std::vector<ForegroundCameraImage>& cameras) const;
  // Renders every view of one frame. A point whose camera index has no image is ignored.
  FrameResult render(const depthfilter::ForegroundCloud& cloud,
                     const std::vector<ForegroundCameraImage>& cameras,
                     const std::vector<CameraModel>& views);

  const VoxelGrid& grid() const { return grid_; }
  // The relic's visibility (SelfOcclusion), built with the renderer; null where the plan leaves
  // it off (a convex or all-metal relic, too little occlusion, or switched off).
  const RelicVisibility* visibility() const { return visibility_.get(); }
  // The visitors' light of the last frame that planned it; null for a relic with no diffuse or
  // very rough surface, or before such a frame.
  const VisitorLight* visitorLight() const { return visitor_light_.get(); }
  // The plinth's caustic of the last relighting (empty without a plinth or a transmissive relic).
  const CausticImage* plinthCaustic() const;
  const TracerSettings& settings() const { return settings_; }
  // Fixes the exposure (> 0) or makes it automatic (<= 0) from the next frame on.
  void setExposure(float exposure);

 private:
  struct ViewCache;
  // plan(), with whether a visitor is within visitor_light_distance, the visitors' largest
  // displayed change this frame, and the axis-aligned filter's and the progressive refinement's at
  // their views' last checks, the largest over the views (each infinite: not measured).
  EffectPlan planFrame(const depthfilter::ForegroundCloud& cloud,
                       const std::vector<ForegroundCameraImage>& cameras, bool visitor_near,
                       float visitor_codes, float filter_codes, float refinement_codes) const;
  // Each view's gate (filter_gate or refinement_gate of its cache) at its last check; infinite
  // where a view has none or is due one (lobe_effect_gate.hpp). shows_cache (optional, per view):
  // a view that shows its cached static shading this frame keeps its last check whatever changed
  // (no pass to check in).
  std::vector<float> gateCodes(const std::vector<CameraModel>& views, LobeEffectGate ViewCache::*gate,
                               const std::vector<bool>* shows_cache) const;
  // The axis-aligned filter's largest displayed change over these views at their last checks.
  float lobeFilterCodes(const std::vector<CameraModel>& views, const std::vector<bool>& shows_cache) const;
  // Each view's progressive refinement's displayed change at its last check.
  std::vector<float> refinementCodes(const std::vector<CameraModel>& views) const;
  // The key of the light the static shading is lit with (the IBL's source and the relic's turn).
  std::uint64_t lightKey() const;
  bool visitorWithinReach(const depthfilter::ForegroundCloud& cloud) const;
  // The exposure the gates weigh a change at: the settings' fixed one, else the largest a view
  // chose in the last frame; 0 before any.
  float gateExposure() const;
  // foreground: foregroundSignature of this frame's grid (progressive_accumulation.hpp); refine:
  // the plan's ProgressiveRefinement and this view's refinement shows (or is due a check);
  // deferred: the view shows its cached static passes although its eye moved beyond the reuse
  // distance (TracerSettings::static_retraces_per_frame).
  ViewImages renderView(const EffectPlan& plan, const std::vector<ForegroundCameraImage>& cameras,
                        const CameraModel& view, std::uint64_t foreground, bool refine, bool deferred,
                        ViewCache& cache) const;

  const RenderScene& scene_;
  const PrefilteredIbl& ibl_;
  TracerSettings settings_;
  bool relic_glossy_ = false;
  bool relic_lit_diffusely_ = false;  // some surface takes the hall's light by a diffuse or a wide lobe
  bool relic_wide_lobes_ = false;     // some material at least kGlossyRoughnessLimit rough
  float last_exposure_ = 0.0f;        // the largest exposure a view chose in the last frame
  bool relic_transmissive_ = false, relic_clearcoat_ = false;
  int internal_depth_ = 0;  // with a transmissive relic: settings' or measured
  float internal_residual_ = 0.0f;
  Bounds3 relic_bounds_;  // of the static relic, for culling primary rays
  VoxelGrid grid_;
  std::vector<ForegroundPyramid> pyramids_;
  // For the relic materials at least foreground_map_roughness rough; null when there is none.
  std::unique_ptr<RoughForegroundMap> rough_map_;
  std::unique_ptr<RelicVisibility> visibility_;
  std::unique_ptr<VisitorLight> visitor_light_;  // made at the first frame that plans it
  // Its lighting under the IBL, lit again when the IBL's panorama or relic turn changes.
  RelicVisibility::Lighting lighting_;
  std::uint64_t lit_source_ = 0;
  float lit_turn_ = 0.0f;
  bool lit_ = false;
  float self_occlusion_codes_ = 0.0f;   // largestDisplayedChange of lighting_
  std::string self_occlusion_figures_;  // "6305 vertex sides, up to 52% occluded"
  std::string self_occlusion_reason_;
  bool refines_ = false;  // ProgressiveRefinement: a rough lobe to refine on an opaque relic
  std::string refinement_reason_;
  bool lobe_filter_ = false;  // the plan's AxisAlignedFilter: some material samples its rough lobe
  std::string lobe_filter_reason_;
  std::vector<std::unique_ptr<ViewCache>> caches_;  // per view slot
  // The interreflection of the lobes at least kGlossyRoughnessLimit rough, per vertex and eye
  // direction, shared by the views (TracerSettings::EvaluationKnobs::wide_lobe_cache); null where
  // no material is that rough or it is off. Its entries hold for the light and plan hashed in
  // wide_lobes_key_.
  std::unique_ptr<WideLobeCache> wide_lobes_;
  std::uint64_t wide_lobes_key_ = 0;
  // The plinth's light (TracerSettings::plinth), relit when the IBL's panorama or relic turn
  // changes; null without a plinth.
  std::unique_ptr<PlinthLight> plinth_light_;
  std::uint64_t plinth_source_ = 0;
  float plinth_turn_ = 0.0f;
  bool plinth_lit_ = false;
};

}  // namespace holo::reflect
