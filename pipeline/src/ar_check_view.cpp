#include "holo/pipeline/ar_check_view.hpp"

#include <chrono>

#include "holo/core/error.hpp"

namespace holo::pipeline {

ar::ArView arCheckView(Installation& installation, int index, ar::ArViewSettings settings, double timeout_s) {
  ar::requireArCameraIndex(index, static_cast<int>(installation.cameras.size()));
  const auto i = static_cast<std::size_t>(index);
  capture::CameraSource& source = *installation.sources.at(i);
  source.open();
  source.start();
  const capture::GrabResult grabbed =
      source.grab(std::chrono::duration_cast<Nanoseconds>(std::chrono::duration<double>(timeout_s)));
  source.stop();
  if (grabbed.status != capture::GrabStatus::Ok)
    throw InputError(
        "camera " + std::to_string(index), source.name(),
        "a frame from the camera within " + std::to_string(timeout_s) + " s (" + grabbed.message + ")");
  RgbdFrame frame = grabbed.frame;
  if (!frame.depth.empty() && frame.depth.type() == CV_32FC1) {
    if (i < installation.depth_correction.size() && installation.depth_correction[i] != 1.0f)
      frame.depth = frame.depth * installation.depth_correction[i];
    if (i < installation.depth_to_colour.size() && installation.depth_to_colour[i] &&
        frame.depth.size() == installation.depth_to_colour[i]->depthSize())
      frame.depth = installation.depth_to_colour[i]->apply(frame.depth);
  }
  ar::requireArCameraInputs(index, installation.cameras[i], frame);
  settings.exposure = installation.camera_exposure;
  settings.panorama_yaw_rad = installation.panorama_yaw_rad;
  return ar::renderArView(index, installation.cameras[i], frame, installation.relic, installation.panorama,
                          settings);
}

}  // namespace holo::pipeline
