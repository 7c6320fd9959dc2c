#include "holo/pipeline/ar_check_view.hpp"

#include <chrono>

#include "holo/core/error.hpp"

namespace holo::pipeline {
namespace {

capture::CameraSource& arSource(Installation& installation, int index) {
  const auto i = static_cast<std::size_t>(index);
  if (i < installation.sources.size()) return *installation.sources[i];
  return *installation.check_sources.at(i - installation.sources.size());
}

const CameraModel& arCamera(const Installation& installation, int index) {
  const auto i = static_cast<std::size_t>(index);
  if (i < installation.cameras.size()) return installation.cameras[i];
  return installation.check_cameras.at(i - installation.cameras.size());
}

void startSource(capture::CameraSource& source) {
  source.open();
  source.start();
}

// The camera's next frame, its depth corrected as the frame loop corrects a rig camera's;
// nullopt at the end of its stream.
std::optional<RgbdFrame> grabFrame(Installation& installation, int index, double timeout_s) {
  capture::CameraSource& source = arSource(installation, index);
  const capture::GrabResult grabbed =
      source.grab(std::chrono::duration_cast<Nanoseconds>(std::chrono::duration<double>(timeout_s)));
  if (grabbed.status == capture::GrabStatus::EndOfStream) return std::nullopt;
  if (grabbed.status != capture::GrabStatus::Ok)
    throw InputError(
        "camera " + std::to_string(index), source.name(),
        "a frame from the camera within " + std::to_string(timeout_s) + " s (" + grabbed.message + ")");
  RgbdFrame frame = grabbed.frame;
  const auto i = static_cast<std::size_t>(index);
  if (!frame.depth.empty() && frame.depth.type() == CV_32FC1) {
    if (i < installation.depth_correction.size() && installation.depth_correction[i] != 1.0f)
      frame.depth = frame.depth * installation.depth_correction[i];
    if (i < installation.depth_to_colour.size() && installation.depth_to_colour[i] &&
        frame.depth.size() == installation.depth_to_colour[i]->depthSize())
      frame.depth = installation.depth_to_colour[i]->apply(frame.depth);
  }
  return frame;
}

}  // namespace

int arCameraCount(const Installation& installation) {
  return static_cast<int>(installation.cameras.size() + installation.check_cameras.size());
}

ar::ArView arCheckView(Installation& installation, int index, ar::ArViewSettings settings, double timeout_s) {
  ar::requireArCameraIndex(index, arCameraCount(installation));
  capture::CameraSource& source = arSource(installation, index);
  startSource(source);
  const std::optional<RgbdFrame> frame = grabFrame(installation, index, timeout_s);
  source.stop();
  if (!frame)
    throw InputError("camera " + std::to_string(index), source.name(), "a frame (the stream ended)");
  const CameraModel& camera = arCamera(installation, index);
  ar::requireArCameraInputs(index, camera, *frame);
  settings.exposure = installation.camera_exposure;
  settings.panorama_yaw_rad = installation.panorama_yaw_rad;
  return ar::renderArView(index, camera, *frame, installation.relic, installation.panorama, settings);
}

ArLiveView::ArLiveView(Installation& installation, int index, ar::LiveCompositeSettings settings,
                       double timeout_s)
    : installation_(installation), index_(index), timeout_s_(timeout_s) {
  ar::requireArCameraIndex(index, arCameraCount(installation));
  settings.view.exposure = installation.camera_exposure;
  settings.view.panorama_yaw_rad = installation.panorama_yaw_rad;
  composite_ = std::make_unique<ar::LiveComposite>(
      index, arCamera(installation, index), installation.panorama, installation.relic, std::move(settings));
  startSource(arSource(installation, index));
}

ArLiveView::~ArLiveView() {
  arSource(installation_, index_).stop();
}

const CameraModel& ArLiveView::camera() const {
  return arCamera(installation_, index_);
}

std::optional<ar::LiveCompositeFrame> ArLiveView::step() {
  const std::optional<RgbdFrame> frame = grabFrame(installation_, index_, timeout_s_);
  if (!frame) return std::nullopt;
  return composite_->add(*frame);
}

}  // namespace holo::pipeline
