// Panorama yaw alignment: the rotation about world +Y that makes the hall panorama agree with
// what a calibrated camera sees. Each candidate yaw renders the camera's view from the panorama
// (holo::equirect, the one direction/pixel convention) and scores it by normalised correlation
// of log luminance with the camera's image; a 1-degree scan over the full circle is refined to
// 0.02 degrees around the best. Parallax (the camera is not at the panorama's centre) is
// ignored: the hall's walls are metres away.
#pragma once

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"

namespace holo::calib {

struct YawFit {
  float yaw_rad = 0.0f;      // pass to holo::equirect as `yaw`; in [-pi, pi)
  double correlation = 0.0;  // normalised correlation at the best yaw, in [-1, 1]
};

// `panorama` CV_32FC3 linear BGR; `image` CV_8UC3 sRGB of the camera's size. Throws InputError
// (naming `source`) for empty or mismatched inputs.
YawFit alignPanoramaYaw(const cv::Mat& panorama, const CameraModel& camera, const cv::Mat& image,
                        const std::string& source = "panorama alignment");

}  // namespace holo::calib
