#include "holo/depthfilter/foreground_scale.hpp"

#include <opencv2/imgproc.hpp>
#include <string>

#include "holo/core/error.hpp"

namespace holo::depthfilter {

void checkForegroundScale(int scale, int width, int height) {
  if (scale < 1 || scale > kMaxForegroundScale)
    throw Error("foreground scale: expected an integer in [1, " + std::to_string(kMaxForegroundScale) +
                "], got " + std::to_string(scale));
  if (width % scale != 0 || height % scale != 0)
    throw Error("foreground scale " + std::to_string(scale) + ": the camera's " + std::to_string(width) +
                "x" + std::to_string(height) + " frames are not a multiple of it");
}

CameraModel reducedCamera(const CameraModel& camera, int scale) {
  if (scale == 1) return camera;
  Intrinsics K = camera.intrinsics();
  const float s = float(scale), centre_offset = 0.5f * float(scale - 1);
  K.width /= scale;
  K.height /= scale;
  K.fx /= s;
  K.fy /= s;
  K.cx = (K.cx - centre_offset) / s;
  K.cy = (K.cy - centre_offset) / s;
  return CameraModel(K, camera.T_world_camera());
}

RgbdFrame reducedFrame(const RgbdFrame& frame, int scale) {
  if (scale == 1 || frame.empty()) return frame;
  RgbdFrame reduced = frame;
  const cv::Size size(frame.colour.cols / scale, frame.colour.rows / scale);
  cv::resize(frame.colour, reduced.colour, size, 0.0, 0.0, cv::INTER_AREA);
  reduced.depth.create(size, CV_32FC1);
  for (int y = 0; y < size.height; ++y) {
    const float* in = frame.depth.ptr<float>(y * scale);
    float* out = reduced.depth.ptr<float>(y);
    for (int x = 0; x < size.width; ++x) out[x] = in[x * scale];
  }
  return reduced;
}

cv::Mat expandedToFull(const cv::Mat& reduced, cv::Size full) {
  if (reduced.empty() || reduced.size() == full) return reduced;
  cv::Mat out;
  cv::resize(reduced, out, full, 0.0, 0.0, cv::INTER_NEAREST);
  return out;
}

}  // namespace holo::depthfilter
