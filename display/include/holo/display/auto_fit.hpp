// Object auto-fit: the part of a face image worth showing. The renderer leaves everything but the
// relic black, so the bounding box of the non-black pixels (or of a coverage mask the renderer
// provides) plus a margin is the crop that makes the relic fill its view on every pyramid face.
#pragma once

#include <opencv2/core.hpp>

#include "holo/display/layout.hpp"

namespace holo::display {

// Crop rectangle (pixels of `image`, x right, y down; always inside the image and non-empty).
//  * `mask` (optional, CV_8UC1 of the image's size): object where mask > 0.
//  * otherwise object where any channel of `image` exceeds settings.threshold (CV_8UC3: on the
//    [0,1] scale, i.e. threshold * 255; CV_32FC3: linear value; NaN counts as black).
// The object's bounding box grows by settings.margin times its larger side on each side and is
// clipped to the image. No object pixel at all gives the whole image.
cv::Rect2f objectCrop(const cv::Mat& image, const cv::Mat& mask, const AutoFitSettings& settings);

}  // namespace holo::display
