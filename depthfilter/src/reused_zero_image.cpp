#include "holo/depthfilter/reused_zero_image.hpp"

#include "holo/core/image_sharing.hpp"

namespace holo::depthfilter {

cv::Mat ReusedZeroImage::next(cv::Size size, int type) {
  // Only image_ refers to the buffer: no image handed out earlier can see it change.
  const bool reusable = !image_.empty() && image_.size() == size && image_.type() == type &&
                        image_.u != nullptr && !sharedElsewhere(image_);
  if (reusable) {
    image_(written_ & cv::Rect(0, 0, size.width, size.height)).setTo(0);
  } else {
    // A new buffer: assigning cv::Mat::zeros would write into the shared one.
    image_ = cv::Mat(size, type, cv::Scalar::all(0));
  }
  written_ = {};
  return image_;
}

void ReusedZeroImage::written(const cv::Rect& box) {
  if (box.empty()) return;
  written_ = written_.empty() ? box : (written_ | box);
}

}  // namespace holo::depthfilter
