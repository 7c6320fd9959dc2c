#include "holo/ar/ar_view.hpp"

#include <cmath>

#include "holo/ar/albedo_estimate.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/environment.hpp"
#include "holo/reflect/irradiance_sh.hpp"

namespace holo::ar {
namespace {

std::string cameraName(int index) {
  return "camera " + std::to_string(index);
}

bool rigid(const mat4& T) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(T[c][r])) return false;
  const mat3 R(T);
  const mat3 RtR = glm::transpose(R) * R;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (std::abs(RtR[c][r] - (c == r ? 1.0f : 0.0f)) > 1e-3f) return false;
  return std::abs(glm::determinant(R) - 1.0f) < 1e-3f && T[0][3] == 0.0f && T[1][3] == 0.0f &&
         T[2][3] == 0.0f && T[3][3] == 1.0f;
}

}  // namespace

void requireArCameraIndex(int index, int count) {
  const std::string name = cameraName(index);
  if (index < 0 || index >= count)
    throw InputError(name, "--ar-camera",
                     count == 0 ? std::string("a camera, but the installation has none")
                                : "a camera index from 0 to " + std::to_string(count - 1) +
                                      " (the installation has " + std::to_string(count) + " camera" +
                                      (count == 1 ? "" : "s") + ")");
}

void requireArCameraInputs(int index, const CameraModel& model, const RgbdFrame& frame) {
  const std::string name = cameraName(index);
  const Intrinsics& K = model.intrinsics();
  if (!(K.fx > 0.0f) || !(K.fy > 0.0f) || K.width <= 0 || K.height <= 0)
    throw InputError(name, "calibration intrinsics",
                     "focal lengths fx, fy > 0 and an image size (calibrate the camera)");
  if (!rigid(model.T_world_camera()))
    throw InputError(
        name, "calibration T_world_camera",
        "a finite rigid camera-to-world pose in the pyramid frame (calibrate the camera's pose)");
  if (frame.colour.empty() || frame.colour.type() != CV_8UC3)
    throw InputError(name, "colour", "a colour image (CV_8UC3 BGR) from the camera");
  if (frame.colour.cols != K.width || frame.colour.rows != K.height)
    throw InputError(name, "colour",
                     "an image of the calibrated size " + std::to_string(K.width) + "x" +
                         std::to_string(K.height) + ", got " + std::to_string(frame.colour.cols) + "x" +
                         std::to_string(frame.colour.rows));
  if (frame.depth.empty())
    throw InputError(name, "depth",
                     "a depth image: the AR view builds the real surfaces from the camera's depth");
  if (frame.depth.type() != CV_32FC1 || frame.depth.size() != frame.colour.size())
    throw InputError(name, "depth",
                     "a CV_32FC1 depth image in metres registered to the colour image (same size)");
  if (cv::countNonZero(frame.depth > 0.0f) == 0)
    throw InputError(name, "depth", "at least one valid depth pixel (the depth image is all invalid)");
}

CameraRealScene realSceneFromCamera(int index, const CameraModel& camera, const RgbdFrame& frame,
                                    const reflect::Environment& environment, float exposure,
                                    const DepthSurfaceSettings& settings) {
  CameraRealScene out;
  out.background = srgb8ToLinear(frame.colour) * (1.0f / (exposure > 0.0f ? exposure : 1.0f));
  DepthSurface real = depthSurface(frame.depth, camera, settings, cameraName(index));
  out.surface.albedo = estimateAlbedo(real, out.background, reflect::IrradianceSH(environment));
  out.surface.mesh = std::move(real.mesh);
  return out;
}

cv::Mat compositeRegion(const LocalScene& scene, const CameraModel& camera, const cv::Mat& background,
                        const ArViewSettings& settings, const RelicCaustic* caustic) {
  if (!settings.trace_change_region) return cv::Mat();
  const float exposure = settings.exposure > 0.0f ? settings.exposure : 1.0f;
  cv::Mat region = changeRegion(scene, camera, background,
                                {.negligible_codes = settings.negligible_codes, .exposure = exposure});
  if (caustic) addCausticToRegion(*caustic, camera, background, settings.negligible_codes, exposure, region);
  return region;
}

ArView renderArView(int index, const CameraModel& camera, const RgbdFrame& frame, const Model& relic,
                    const cv::Mat& panorama, const ArViewSettings& settings) {
  const reflect::Environment environment(panorama, settings.panorama_yaw_rad);
  const float exposure = settings.exposure > 0.0f ? settings.exposure : 1.0f;
  CameraRealScene real = realSceneFromCamera(index, camera, frame, environment, exposure, settings.surface);
  ArView out;
  out.real_vertices = real.surface.mesh.positions.size();
  const LocalScene scene(std::move(real.surface), relic, environment);
  const std::optional<RelicCaustic> caustic = traceRelicCaustic(relic, environment, settings.caustic);
  out.caustic_photons = caustic ? caustic->image().traced : 0;
  const CompositeImage composite = renderComposite(
      scene, camera, real.background, settings.composite,
      compositeRegion(scene, camera, real.background, settings, caustic ? &*caustic : nullptr), frame.depth,
      caustic ? &*caustic : nullptr);
  out.radiance = filterChange(composite.radiance, real.background, composite.relic_coverage, frame.depth,
                              settings.filter);
  out.image = linearToSrgb8(out.radiance, exposure);
  out.relic_pixels = cv::countNonZero(composite.relic_coverage > 0.0f);
  out.rays = composite.rays;
  return out;
}

}  // namespace holo::ar
