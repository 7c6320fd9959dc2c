// The AR check view of one camera, live and refined while still: each frame adds a pass of
// delta path tracing (ar_view.hpp's composite, settings.view.composite.spp samples per pixel) to
// the samples accumulated since the camera's picture last changed, so a still view converges
// frame by frame to the composite of many samples, the way the pyramid views' rough lobes refine
// (reflect's ProgressiveRefinement). The local real scene (the depth surface and its albedo) is
// built from the frame an accumulation starts on and kept while the view is still; every frame's
// pass continues one sample sequence (CompositeSettings::first_sample).
//
// Still: the camera's image and depth have not changed since the accumulation's first frame
// (StillnessSettings: the sensor's noise is not a change, a visitor walking into the picture or
// a moved camera is) and the relic is the same. A frame that is not still starts a new
// accumulation on itself, so the view follows the change in that frame; where only its colour
// changed (its depth still), the depth surface and its ray scene are kept and only the albedo and
// the background are made anew.
// Units: metres, world (pyramid) frame; images as ar_view.hpp.
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "holo/ar/ar_view.hpp"
#include "holo/ar/local_scene.hpp"
#include "holo/reflect/irradiance_sh.hpp"

namespace holo::ar {

// When a frame is a change against the accumulation's first frame. A pixel has changed when its
// luma, averaged over a (2 blur_radius + 1)^2 window (the sensor's noise averages out), moved by
// more than colour_codes 8-bit codes, or when its depth (valid in both) moved by more than
// depth_ratio of itself; the frame is a change when more than changed_fraction of its pixels have.
struct StillnessSettings {
  int blur_radius = 2;              // pixels, >= 0
  float colour_codes = 8.0f;        // 8-bit codes, > 0
  float depth_ratio = 0.05f;        // > 0
  double changed_fraction = 0.002;  // [0, 1)
};

struct LiveCompositeSettings {
  ArViewSettings view;  // view.composite.spp: the samples per pixel each frame adds
  StillnessSettings still;
  // The accumulation stops adding passes at this many samples per pixel (later still frames
  // cost only the change test and the filter), >= view.composite.spp.
  int max_samples = 1024;
};

struct LiveCompositeFrame {
  cv::Mat image;          // CV_8UC3 sRGB BGR at the camera's exposure, the change filtered
  cv::Mat radiance;       // CV_32FC3 linear BGR, filtered
  cv::Mat unfiltered;     // CV_32FC3 linear BGR: the accumulated composite before the filter
  int samples = 0;        // samples per pixel accumulated in it
  bool reset = false;     // this frame started a new accumulation (the first frame does)
  double changed = 0.0;   // share of the pixels changed against the accumulation's first frame
  int relic_pixels = 0;   // pixels whose samples met the relic
  int traced_pixels = 0;  // pixels the pass traces (the change region's)
  std::int64_t rays = 0;  // cast for this frame
  double ms = 0.0;        // wall-clock time add() took (the change test, the pass, the filter)
  double cpu_ms = 0.0;    // CPU time of the process's threads while add() ran (all cores together)
};

class LiveComposite {
 public:
  // `panorama`: CV_32FC3 linear BGR equirectangular (copied). Throws InputError on settings out of range.
  LiveComposite(int index, CameraModel camera, const cv::Mat& panorama, const Model& relic,
                LiveCompositeSettings settings);
  ~LiveComposite();
  LiveComposite(const LiveComposite&) = delete;
  LiveComposite& operator=(const LiveComposite&) = delete;

  // A new relic (a playlist's next entry): the next frame starts a new accumulation.
  void setRelic(const Model& relic);
  // One frame of the camera (refused as requireArCameraInputs refuses it): its composite.
  LiveCompositeFrame add(const RgbdFrame& frame);
  int samples() const { return samples_; }
  // Depth surfaces (and their ray scenes) built so far: one per accumulation whose depth changed.
  int surfacesBuilt() const { return surfaces_built_; }

 private:
  void restart(const RgbdFrame& frame);
  // A new accumulation on a frame whose depth is still: the albedo and the background anew.
  void recolour(const RgbdFrame& frame);
  // The box of the pixels the relic may change, widened by two filter radii (empty: none).
  cv::Rect changeBox() const;

  int index_;
  CameraModel camera_;
  LiveCompositeSettings settings_;
  Model relic_;
  std::unique_ptr<reflect::Environment> environment_;    // the scene keeps a reference to it
  std::unique_ptr<reflect::IrradianceSH> irradiance_;    // the panorama's, for the albedo
  std::shared_ptr<const RelicGeometry> relic_geometry_;  // built once per relic
  std::optional<RelicCaustic> caustic_;                  // traced once per relic (none: opaque)
  std::vector<ivec2> surface_pixels_;                    // the depth surface's vertices' pixels
  int surfaces_built_ = 0;
  std::unique_ptr<LocalScene> scene_;
  bool relic_changed_ = true;
  cv::Mat reference_luma_;    // CV_32FC1, blurred, of the accumulation's first frame
  cv::Mat reference_depth_;   // CV_32FC1
  cv::Mat reference_colour_;  // CV_8UC3: the image shown outside changeBox()
  cv::Mat background_;        // CV_32FC3 radiance of the accumulation's first frame
  cv::Mat region_;            // CV_8UC1: the pixels traced (compositeRegion), empty: all
  cv::Mat sum_;               // CV_32FC3: sum over the accumulated samples of the composite
  cv::Mat coverage_sum_;      // CV_32FC1: sum of the relic's coverage
  int samples_ = 0;
};

// The share of pixels that changed between two frames (see StillnessSettings); `reference_luma`
// is blurredLuma of the earlier frame's colour.
cv::Mat blurredLuma(const cv::Mat& colour, const StillnessSettings& settings);
double changedShare(const cv::Mat& reference_luma, const cv::Mat& reference_depth, const cv::Mat& luma,
                    const cv::Mat& depth, const StillnessSettings& settings);

}  // namespace holo::ar
