#include "holo/eval/displayed_reflection.hpp"

#include <algorithm>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/core/median.hpp"
#include "holo/depthfilter/border_expansion.hpp"
#include "holo/display/eye_tracker.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/reflect/view.hpp"

namespace holo::eval {

RendererInput rendererInput(std::span<const CameraModel> cameras, std::span<const MethodCameraFrame> frames,
                            float camera_exposure) {
  if (frames.size() != cameras.size()) throw Error("rendererInput: one frame per camera expected");
  if (!(camera_exposure > 0.0f)) throw Error("rendererInput: the cameras' exposure must be positive");
  RendererInput input;
  input.cameras.resize(frames.size());
  const depthfilter::BorderExpansionConfig border_config;
  for (std::size_t c = 0; c < frames.size(); ++c) {
    const MethodCameraFrame& f = frames[c];
    if (f.colour.empty()) continue;
    reflect::ForegroundCameraImage& image = input.cameras[c];
    image.camera = cameras[c];
    image.colour_bgr = srgb8ToLinear(f.colour) / camera_exposure;
    image.mask = f.mask;
    if (f.depth.empty()) continue;
    const depthfilter::BorderLayer border = depthfilter::expandBorder(f.mask, f.depth, border_config);
    for (int y = 0; y < f.depth.rows; ++y)
      for (int x = 0; x < f.depth.cols; ++x) {
        float d = f.depth.at<float>(y, x), w = 1.0f;
        if (!(d > 0.0f)) {
          d = border.depth.at<float>(y, x);
          w = border.weight.at<float>(y, x);
          if (!(d > 0.0f) || !(w > 0.0f)) continue;
        }
        depthfilter::ForegroundPoint p;
        p.position = cameras[c].unproject(vec2(float(x), float(y)), d);
        p.radiance = rgbAt(image.colour_bgr, x, y);
        p.weight = std::min(w, 1.0f);
        p.camera = std::uint16_t(c);
        p.x = std::uint16_t(x);
        p.y = std::uint16_t(y);
        if (isFinite(p.position) && isFinite(p.radiance)) input.cloud.points.push_back(p);
      }
  }
  return input;
}

std::vector<CameraModel> defaultFaceViews(const reflect::RenderScene& scene, int size) {
  const Bounds3 bounds = scene.relicBounds();
  const vec3 target = bounds.empty() ? vec3(0.0f) : bounds.center();
  const display::EyeTrackerSettings eyes = pipeline::FrameLoopOptions{}.eyes;
  std::vector<CameraModel> views;
  for (int face = 0; face < 4; ++face) {
    const vec3 eye = display::defaultEye(face, eyes);
    views.push_back(reflect::lookAtCamera(eye, target, reflect::framingFovDeg(eye, bounds), size, size));
  }
  return views;
}

DisplayedReflection::DisplayedReflection(const reflect::RenderScene& scene,
                                         const reflect::PrefilteredIbl& ibl, std::vector<CameraModel> cameras,
                                         float camera_exposure, std::vector<CameraModel> views)
    : cameras_(std::move(cameras)),
      views_(std::move(views)),
      camera_exposure_(camera_exposure),
      renderer_(scene, ibl, pipeline::liveTracerSettings()) {}

DisplayedFrame DisplayedReflection::render(std::span<const MethodCameraFrame> frames) {
  const RendererInput input = rendererInput(cameras_, frames, camera_exposure_);
  reflect::FrameResult result = renderer_.render(input.cloud, input.cameras, views_);
  DisplayedFrame out;
  std::vector<double> exposures;
  for (reflect::ViewImages& v : result.views) {
    out.display.push_back(std::move(v.display));
    out.weight.push_back(std::move(v.weight));
    exposures.push_back(v.exposure);
  }
  if (!exposures.empty()) last_exposure_ = float(median(exposures));
  return out;
}

}  // namespace holo::eval
