// A panel's name written into its top left corner, for the evaluations' side-by-side pictures.
#pragma once

#include <opencv2/imgproc.hpp>
#include <string>

namespace holo::eval {

inline cv::Mat labelled(cv::Mat picture, const std::string& label) {
  cv::putText(picture, label, {8, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(255, 255, 255), 2);
  return picture;
}

}  // namespace holo::eval
