// Supersampling of sparkles (internal): the refraction pass's further paths where a pixel's
// transmitted light disagrees (TracerSettings::refraction_supersample_contrast C > 0).
//
// Where the transmitted light of a four-sample pixel's samples (before the visitors) spans more
// than C in luminance (a sparkle: some of the pixel's rays see a lamp through a crystal's facets,
// the others do not), each of its transmissive samples takes the mean of 16 paths on a 4x4 grid
// across its quarter of the pixel (the rotated grid puts one sample in each quarter). Each is a
// further primary ray (those that miss the relic or meet an opaque material are left out of the
// mean) traced through the relic like the sample's own (glass_transport.hpp), and its exit ray is
// walked for the visitors every frame. The entry's own reflection and diffuse stay the sample's.
// Pixels with one sample (the live loop's edge anti-aliasing leaves a facet's inside so) are not
// measured.
#pragma once

#include <cstdint>

#include "foreground_walk.hpp"
#include "glass_transport.hpp"
#include "holo/core/camera_model.hpp"
#include "holo/reflect/foreground_camera_image.hpp"
#include "holo/reflect/foreground_pyramid.hpp"
#include "holo/reflect/frame_result.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/tracer_settings.hpp"

namespace holo::reflect {

// A sample whose transmitted light is the mean of the paths across its quarter of the pixel:
// those of a grid of primary rays there that meet a transmissive material (its own path alone
// where none does).
struct SupersampledPaths {
  static constexpr int kGrid = 4;  // rays per side of the quarter
  static constexpr int kMaxPaths = kGrid * kGrid;
  int count = 0;  // paths[0, count), entry weights applied
  TransmittedPath paths[kMaxPaths];
};

class RefractionSupersampling {
 public:
  // Everything must outlive this; depth: the transmitted paths' cap of interface events.
  RefractionSupersampling(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                          int depth);

  // Whether a four-sample pixel's transmitted light spans more than the supersampling contrast.
  bool sparkles(const TransmittedPath (&paths)[4], const bool (&transmits)[4]) const;
  // The paths across a sub-sample's quarter of the pixel (`offset` from the pixel's `centre`), of
  // primary rays from `view`; `own` where none meets the glass. Returns the Embree rays cast.
  std::uint64_t supersample(const CameraModel& view, const vec2& centre, const vec2& offset,
                            const TransmittedPath& own, SupersampledPaths& more) const;

 private:
  const RenderScene& scene_;
  const PrefilteredIbl& ibl_;
  const TracerSettings& settings_;
  int depth_;
  float dark_ = 0.0f;  // radiance below which the supersampling contrast is not measured
};

// One path standing for all of a supersampled sample's in the static shading: the mean of their
// weights and of the IBL their exits read, weighted by their scales (the exit rays are each
// walked, walkSupersampledPaths).
TransmittedPath meanPath(const SupersampledPaths& more);

// The visitors along each of a supersampled sample's exit rays, as one sample the composition
// reads with the mean path's scale: weight 1 where any path sees one, the radiance such that
// scale x radiance is the paths' mean of scale x (the IBL and visitors along its exit ray).
// Returns the rays walked.
std::uint64_t walkSupersampledPaths(const SupersampledPaths& more, const ForegroundWalk& walk,
                                    ForegroundSample& out);

}  // namespace holo::reflect
