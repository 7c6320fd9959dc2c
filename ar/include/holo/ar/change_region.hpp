// The pixels of a composite whose displayed value the relic can change, so delta path tracing
// traces only those (elsewhere the composite is the camera's image). A pixel is in the region
// when a sample through it may meet the relic (the relic's bounding sphere, widened by the
// pixel's footprint), or when its real surface point p (the centre ray's hit on the local real
// scene) may see its light changed by a displayed amount:
//  * the relic's bounding sphere is within p's hemisphere (a sphere wholly below p's tangent
//    plane changes nothing there, exactly), and
//  * either it may hide one of the panorama's bright directions from p (the sphere against each
//    bright direction's cone: p may be in the relic's hard shadow), or the largest change of the
//    rest may move p's displayed code by at least `negligible_codes`: albedo / pi * (the
//    sphere's projected solid angle at p) * (L_dim + E_bright / pi), where L_dim bounds the
//    panorama's radiance outside its bright directions (what the relic may hide) and a relic
//    that reflects everything it receives sends at most L_dim + E_bright / pi (E_bright the
//    irradiance of the bright directions at normal incidence) towards p from a convex shape. A
//    relic with glass may focus the bright light (a caustic): it may send up to the panorama's
//    largest radiance (refraction keeps radiance), the bound used for it instead.
// The region is dilated by one pixel: a sample's jitter and a depth edge's neighbour. The bound
// is the first level of delta path tracing's (light the relic blocks or adds at p); the change
// that reaches p only through another real surface's change is not bounded (a second-order
// term: the real albedo times a change the region already holds). A finite panorama proxy
// (parallax) or a camera inside the sphere makes the region every pixel.
// Units: pixels; radiance linear as the composite's; codes of the displayed 8-bit sRGB image.
#pragma once

#include <opencv2/core.hpp>

#include "holo/ar/local_scene.hpp"
#include "holo/core/camera_model.hpp"

namespace holo::ar {

struct ChangeRegionSettings {
  float negligible_codes = 0.5f;  // > 0: a bound below this many displayed codes is no change
  float exposure = 1.0f;          // the displayed code of radiance L is 255 sRGB(exposure L)
};

// The panorama split into bright directions and the rest, as the region's bound reads it: the
// panorama in cells of at most kCells x kCells / 2, a cell bright when its largest pixel exceeds
// kBrightOverMean times the panorama's mean radiance.
struct PanoramaLightBound {
  struct Cone {
    vec3 direction{0.0f, 1.0f, 0.0f};  // unit, away from the scene
    float half_angle = 0.0f;           // radians: the cone holds every direction of the cell
  };
  std::vector<Cone> bright;
  vec3 dim_radiance{0.0f};       // the largest radiance outside the bright cells, per channel
  vec3 max_radiance{0.0f};       // the largest radiance of all, per channel
  vec3 bright_irradiance{0.0f};  // the integral of the bright cells' radiance over solid angle
  static constexpr int kCells = 64;
  static constexpr float kBrightOverMean = 8.0f;
};
PanoramaLightBound panoramaLightBound(const reflect::Environment& environment);

// CV_8UC1 of the camera's size: 255 where the composite may differ from `background` (CV_32FC3,
// the camera's image as radiance), 0 where it is the background.
cv::Mat changeRegion(const LocalScene& scene, const CameraModel& camera, const cv::Mat& background,
                     const ChangeRegionSettings& settings);

}  // namespace holo::ar
