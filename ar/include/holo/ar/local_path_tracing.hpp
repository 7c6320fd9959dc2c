// Path tracing of the local scene (local_scene.hpp) seen through a camera, and the AR composite
// over that camera's image by differential rendering, two ways:
//  * delta path tracing (Xu et al., Sec. 3): at the primary hit of a real surface only the change
//    the relic makes is traced: the panorama's light the relic blocks there (by environment
//    sampling and by BSDF sampling, combined by the balance heuristic, the paper's MIS) and what
//    a BSDF-sampled ray that meets the relic brings instead of what it would have met (the relic's
//    radiance, path traced in the mixed scene, minus the real scene's radiance along it); a
//    BSDF-sampled ray that meets a real surface carries that surface's own change (the same
//    estimator, recursively, `delta_bounces` levels). Where the real scene does not change, no
//    radiance is traced at all;
//  * plain differential rendering (Debevec): the mixed and the real scene path traced apart, their
//    difference added; with independent samples (kTwoPass), or with shared samples
//    (kTwoPassSharedSamples: each pixel sample's real-scene path draws the same random numbers as
//    its mixed-scene path, so where the relic does not intervene the two paths are one and their
//    difference is exactly 0, the way one renderer run twice with one seed correlates its two
//    images; the strongest plain two-pass renderer).
// Either way a pixel sample that meets the relic first is the mixed scene's path-traced radiance
// (mask M of Xu et al. Eq. 1); one that meets a real surface is the camera's radiance L_b plus
// the difference; one that meets nothing (beyond the local scene) is L_b.
//
// Paths: at most max_bounces scatterings (what the last one reaches counts: the panorama); at
// every non-mirror vertex the panorama is sampled (next-event estimation) and combined with BSDF
// sampling by the balance heuristic. A relic's glass (local_scene.hpp's RelicGlass) reflects or
// refracts a path without counting as a scattering (up to 16 such events), so the camera's real
// surroundings and the panorama are seen through it and it casts a shadow lit by what it
// transmits (found by BSDF sampling only: light sampling cannot see through a refracting surface). Pixel
// samples are jittered over the pixel (pixel centres at integer coordinates, OpenCV's convention) and seeded
// per pixel and sample, so images are the same for a seed whatever the thread count, and passes with
// first_sample continue one sequence. Images: CV_32FC3 linear BGR radiance, the camera's size.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "holo/ar/local_scene.hpp"
#include "holo/ar/relic_caustic.hpp"
#include "holo/core/camera_model.hpp"

namespace holo::ar {

enum class DifferentialMethod { kDeltaPathTracing, kTwoPass, kTwoPassSharedSamples };

struct CompositeSettings {
  DifferentialMethod method = DifferentialMethod::kDeltaPathTracing;
  int spp = 16;  // pixel samples, >= 1
  // Pixels where the relic is seen (the centre ray of the pixel or of one of its 8 neighbours
  // meets the relic first) take relic_spp_factor x spp samples, >= 1: the relic's pixels are the
  // mixed scene path traced, as noisy under every method, while delta path tracing's change on
  // the real pixels is quiet; its time is better spent on the relic. Their samples are numbered
  // from first_sample x relic_spp_factor, so passes continue one sequence there too.
  int relic_spp_factor = 1;
  int first_sample = 0;   // index of the first sample (a later pass continues the sequence)
  int max_bounces = 3;    // scatterings per path, >= 1
  int delta_bounces = 3;  // delta path tracing: real-surface levels whose change is traced, >= 1
  std::uint64_t seed = 1;
};

struct CompositeImage {
  cv::Mat radiance;        // the composite, linear
  cv::Mat relic_coverage;  // CV_32FC1: the fraction of a pixel's samples that met the relic first
  std::int64_t rays = 0;   // rays cast (intersection and occlusion), the renderer's cost in rays
};

// `background`: the camera's image as radiance (CV_32FC3 linear BGR, the camera's size).
// `region` (CV_8UC1 of that size, change_region.hpp): pixels at 0 are the background, untraced,
// with no relic coverage; empty: every pixel is traced.
// `depth` (CV_32FC1 metres, camera-frame z, 0 = invalid, the camera's size; empty: none): the
// camera's depth registered to `background`. With it, a relic pixel's path that meets a real
// surface the camera sees (its depth within 3% of the camera's at its pixel, the same side) takes
// that surface's radiance as measured, the background's pixel, plus the relic's change there
// (delta path tracing, `delta_bounces` levels), instead of path tracing the local scene's model of
// it: the relic reflects the real room as the camera saw it. Every method shades the relic's
// pixels this way; the real pixels are where they differ.
// `caustic` (relic_caustic.hpp; nullptr: none): where delta path tracing traces a real surface's
// change on the receiver (a real pixel's, or one the relic's pixel sees), the caustic's light
// tracer brings the light the relic's glass focuses there, and BSDF sampling leaves those paths
// out. The two-pass renderers' real pixels keep their own path-traced caustic.
CompositeImage renderComposite(const LocalScene& scene, const CameraModel& camera, const cv::Mat& background,
                               const CompositeSettings& settings, const cv::Mat& region = cv::Mat(),
                               const cv::Mat& depth = cv::Mat(), const RelicCaustic* caustic = nullptr);

// The local scene `content` path traced through the camera (pixels beyond it: the panorama).
// Two renders with one seed share their random numbers wherever the relic does not intervene.
CompositeImage renderLocalScene(const LocalScene& scene, SceneContent content, const CameraModel& camera,
                                const CompositeSettings& settings);

}  // namespace holo::ar
