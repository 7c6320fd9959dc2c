// Evaluation only: a reference for measuring the appliance's renderer, never linked by it
// (reference/CMakeLists.txt).
// Image comparisons of the evaluation (paper Sec. 4.1.2, Table 1). Images are linear HDR
// CV_32FC3 of the same size; values are compared as displayed before encoding, i.e. clamped to
// [0, 1] (a monitor cannot show more), so one blown-out sun pixel does not dominate an MSE.
// MSE = mean over the pixels (and the 3 channels) of the squared difference.
#pragma once

#include <opencv2/core.hpp>

namespace holo::reference {

inline constexpr float kForegroundDistance = 0.2f;  // paper: RGB distance >= 0.2

// Dynamic-foreground reflection region: CV_8UC1, 255 where the ground truths with and without
// the visitors differ by a Euclidean RGB distance >= threshold.
cv::Mat foregroundRegion(const cv::Mat& gt_with, const cv::Mat& gt_without,
                         float threshold = kForegroundDistance);
// MSE over the pixels where mask != 0 (all pixels when mask is empty); 0 for an empty region.
double mse(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask = {});
// Colour-coded per-pixel squared error (inferno), 0 .. max_error mapped to dark .. bright.
cv::Mat errorMap(const cv::Mat& a, const cv::Mat& b, float max_error = 0.05f);

}  // namespace holo::reference
