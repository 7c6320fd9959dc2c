// What the pyramid's faces display of the relic when the live reflection renderer is fed one depth
// method's output: each camera's foreground depth back-projected with its border expanded and its
// colour linearised as the live foreground pipeline hands them on (depthfilter::expandBorder with
// the default settings, radiance = sRGB linearised / the cameras' exposure), rendered by
// reflect::FrameRenderer with the live loop's tracer settings (pipeline::liveTracerSettings) into
// the four face views from the default standing eyes (display::defaultEye, the live view size).
// One instance per method: the renderer keeps per-view caches across frames, as live.
// Units: metres; images as reflect::ViewImages.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"
#include "holo/eval/reflection_flicker.hpp"
#include "holo/reflect/foreground_camera_image.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::eval {

// One camera's frame as a method hands it to the renderer.
struct MethodCameraFrame {
  cv::Mat colour;  // CV_8UC3 sRGB BGR, the camera's frame
  cv::Mat mask;    // CV_8UC1, non-zero = foreground (what the pyramids read the colour inside)
  cv::Mat depth;   // CV_32FC1 metres, 0 = no depth (the method's output)
};

// The foreground cloud and camera images the live pipeline would hand the renderer for these
// frames (one per camera, in the cameras' order; an empty frame contributes nothing).
struct RendererInput {
  depthfilter::ForegroundCloud cloud;
  std::vector<reflect::ForegroundCameraImage> cameras;
};
RendererInput rendererInput(std::span<const CameraModel> cameras, std::span<const MethodCameraFrame> frames,
                            float camera_exposure);

// The four face views of the live loop: from display::defaultEye of each face towards the relic's
// centre, framing it, `size` pixels square.
std::vector<CameraModel> defaultFaceViews(const reflect::RenderScene& scene, int size);

class DisplayedReflection {
 public:
  // scene and ibl must outlive this. The exposure starts automatic (setExposure fixes it).
  DisplayedReflection(const reflect::RenderScene& scene, const reflect::PrefilteredIbl& ibl,
                      std::vector<CameraModel> cameras, float camera_exposure,
                      std::vector<CameraModel> views);
  // The faces' display and foreground weight for one frame of every camera.
  DisplayedFrame render(std::span<const MethodCameraFrame> frames);
  // The median over the views of the exposure the last render chose (what the live loop fixes).
  float lastExposure() const { return last_exposure_; }
  void setExposure(float exposure) { renderer_.setExposure(exposure); }

 private:
  std::vector<CameraModel> cameras_, views_;
  float camera_exposure_;
  reflect::FrameRenderer renderer_;
  float last_exposure_ = 1.0f;
};

}  // namespace holo::eval
