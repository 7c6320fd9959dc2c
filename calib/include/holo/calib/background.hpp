// Background capture: the empty hall as each camera sees it (the depth filter's gamma_s), made
// robust by combining many frames: per pixel, the median colour and the median of the valid
// depths; depth that is missing, NaN, infinite or negative is invalid and counted.
#pragma once

#include <string>
#include <vector>

#include "holo/core/rgbd_frame.hpp"

namespace holo::calib {

struct BackgroundModel {
  cv::Mat colour;         // CV_8UC3 BGR: per-pixel, per-channel median
  cv::Mat depth;          // CV_32FC1 metres: median of the valid depths; 0 when fewer than half valid
  cv::Mat invalid_count;  // CV_16UC1: frames in which the pixel's depth was invalid
  int frames = 0;
  double invalid_fraction = 0.0;  // share of pixels whose background depth is 0 (invalid)
  double colour_mad = 0.0;        // mean over pixels of the grey level's median absolute deviation
  long long invalid_samples = 0;  // total invalid depth samples (frames x pixels)
};

// Throws InputError (naming `source`) with no frames or frames of differing size or type.
BackgroundModel captureBackground(const std::vector<RgbdFrame>& frames,
                                  const std::string& source = "background");

}  // namespace holo::calib
