#pragma once

#include <opencv2/core.hpp>

namespace holo::depthfilter {

// A frame-sized image that is zero outside the box its user writes each frame (a stage's output
// outside the foreground's box). next() hands out the same buffer again when nobody else still
// holds it, clearing only the box written last; otherwise (a caller kept the last output) it
// allocates a fresh zero image, so an image handed out earlier never changes. Clearing a box
// instead of the whole frame, in memory already mapped, saves a whole-frame clear and its page
// faults every frame.
class ReusedZeroImage {
 public:
  // An image of `size` and `type` that is zero everywhere. The returned header shares the buffer
  // with this object; the caller must call written() with every pixel it sets to non-zero.
  cv::Mat next(cv::Size size, int type);
  // The box (in the image's pixels) that holds every non-zero pixel written since next().
  void written(const cv::Rect& box);

 private:
  cv::Mat image_;
  cv::Rect written_;  // holds every non-zero pixel of image_
};

}  // namespace holo::depthfilter
