// The AR check view of one camera: the relic at its place in the pyramid frame as camera N sees
// it through its calibrated intrinsics and pose, composited over the camera's colour image with
// its shadow and its light on the real surfaces around it: the local real scene from the
// camera's depth (depth_surface.hpp) with albedo from its colour under the panorama's irradiance
// (albedo_estimate.hpp), the relic's effect on it by delta path tracing
// (local_path_tracing.hpp), its change on the real surfaces filtered (change_filter.hpp).
// Units: metres, world (pyramid) frame; images as RgbdFrame (colour CV_8UC3 sRGB BGR, depth
// CV_32FC1 metres).
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "holo/ar/change_filter.hpp"
#include "holo/ar/change_region.hpp"
#include "holo/ar/depth_surface.hpp"
#include "holo/ar/local_path_tracing.hpp"
#include "holo/ar/relic_caustic.hpp"
#include "holo/core/camera_model.hpp"
#include "holo/core/mesh.hpp"
#include "holo/core/rgbd_frame.hpp"
#include "holo/reflect/environment.hpp"

namespace holo::ar {

// Refuse a camera the view cannot be made for, with an InputError naming "camera N" and what is
// needed. An index outside 0..count-1 (the count said):
void requireArCameraIndex(int index, int count);
// A model without calibration (focal lengths > 0, an image size, a finite rigid T_world_camera),
// a frame without colour of the calibrated size, or without depth (CV_32FC1 of the colour's size
// with at least one valid pixel):
void requireArCameraInputs(int index, const CameraModel& model, const RgbdFrame& frame);

// The real part of the local scene as camera `index` sees it: the depth surface with the albedo
// estimated from the colour under `environment`'s irradiance, and the colour as radiance
// (srgbToLinear / exposure, CV_32FC3 linear BGR), what the composite is added to.
struct CameraRealScene {
  RealSurface surface;
  cv::Mat background;
};
CameraRealScene realSceneFromCamera(int index, const CameraModel& camera, const RgbdFrame& frame,
                                    const reflect::Environment& environment, float exposure,
                                    const DepthSurfaceSettings& settings);

struct ArViewSettings {
  CompositeSettings composite;
  ChangeFilterSettings filter;
  DepthSurfaceSettings surface;  // centred on the pyramid frame's origin, where the relic stands
  float exposure = 1.0f;         // the camera's: radiance = srgbToLinear(colour) / exposure
  float panorama_yaw_rad = 0.0f;
  // Trace only the pixels the relic can change (change_region.hpp; its exposure is `exposure`);
  // false: every pixel.
  bool trace_change_region = true;
  float negligible_codes = 0.5f;  // ChangeRegionSettings::negligible_codes
  // The caustic of a transmissive relic on the pyramid base (relic_caustic.hpp; enabled: false for none).
  RelicCausticSettings caustic;
};

// The region renderComposite traces under `settings` (empty: every pixel), with the pixels the
// relic's caustic may change (none: no caustic).
cv::Mat compositeRegion(const LocalScene& scene, const CameraModel& camera, const cv::Mat& background,
                        const ArViewSettings& settings, const RelicCaustic* caustic = nullptr);

struct ArView {
  cv::Mat image;                  // CV_8UC3 sRGB BGR: the composite at the camera's exposure
  cv::Mat radiance;               // CV_32FC3 linear BGR
  int relic_pixels = 0;           // pixels whose samples met the relic (0: out of the camera's view)
  std::size_t real_vertices = 0;  // of the local real surface
  std::int64_t rays = 0;
  std::uint64_t caustic_photons = 0;  // traced for the relic's caustic (0: an opaque relic, none)
};

// The composite of camera `index` (after requireArCameraInputs on it); `panorama`: CV_32FC3 linear BGR
// equirectangular.
ArView renderArView(int index, const CameraModel& camera, const RgbdFrame& frame, const Model& relic,
                    const cv::Mat& panorama, const ArViewSettings& settings);

}  // namespace holo::ar
