// One foreground camera of a frame as the reflection tracer reads it: its model and the filtered
// colour and mask it saw (the pyramids are built from them, the walk reads them through the
// pyramids). Units: linear radiance; images in OpenCV's BGR order.
#pragma once

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"

namespace holo::reflect {

struct ForegroundCameraImage {
  CameraModel camera;
  cv::Mat colour_bgr;  // CV_32FC3 linear; read only inside the mask's non-zero bounding box
  cv::Mat mask;        // CV_32FC1 [0, 1] or CV_8UC1
};

}  // namespace holo::reflect
