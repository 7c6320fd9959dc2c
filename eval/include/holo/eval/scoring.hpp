// How the evaluations score a rendered view: as the pyramid displays it (Reinhard tone map at the
// ground truth's exposure, sRGB, floats in [0, 1]), over the whole view (mse) and over the
// foreground region (fg_mse): the pixels where the visitors change the displayed truth by an RGB
// distance of at least a threshold (reference::foregroundRegion).
#pragma once

#include <string>

#include <opencv2/core.hpp>

namespace holo::eval {

// An HDR image as the pyramid displays it at `exposure`: CV_32FC3 in [0, 1].
cv::Mat displayedImage(const cv::Mat& hdr, float exposure);

struct ForegroundScoring {
  float exposure = 1.0f;  // the ground truth's automatic exposure (reflect::autoExposure)
  cv::Mat truth;          // the ground truth with the visitors, displayed
  cv::Mat region;         // CV_8UC1, 255 in the foreground region
  int region_pixels = 0;

  cv::Mat displayed(const cv::Mat& hdr) const { return displayedImage(hdr, exposure); }
  double mse(const cv::Mat& hdr) const;            // whole view
  double foregroundMse(const cv::Mat& hdr) const;  // the region; 0 when it is empty
};

// truth_hdr: with the visitors; without_hdr: the same view without them (both linear HDR).
ForegroundScoring foregroundScoring(const cv::Mat& truth_hdr, const cv::Mat& without_hdr, float threshold);

// Writes FILE.exr and, beside it, FILE.png (tone mapped with `exposure`, automatic when <= 0).
void writeImagePair(const std::string& exr_path, const cv::Mat& hdr, float exposure = 0.0f);

}  // namespace holo::eval
