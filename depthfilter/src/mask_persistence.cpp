#include "holo/depthfilter/mask_persistence.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/depthfilter/precursor_flow.hpp"

namespace holo::depthfilter {

MaskPersistence::MaskPersistence(MaskPersistenceConfig config) : config_(config) {
  if (!(config_.colour_max >= 0.0f && config_.colour_max <= 765.0f))
    throw Error("MaskPersistence: colour_max must be in [0, 765], got " + std::to_string(config_.colour_max));
  if (config_.max_motion_px < 0)
    throw Error("MaskPersistence: max_motion_px must be >= 0, got " + std::to_string(config_.max_motion_px));
}

void MaskPersistence::reset() {
  previous_mask_.release();
  previous_colour_.release();
}

cv::Rect MaskPersistence::searchBox(const cv::Size& size) const {
  if (!config_.enabled || previous_mask_.size() != size || previous_box_.empty()) return {};
  const int reach = config_.max_motion_px;
  return cv::Rect(previous_box_.x - reach, previous_box_.y - reach, previous_box_.width + 2 * reach,
                  previous_box_.height + 2 * reach) &
         cv::Rect(0, 0, size.width, size.height);
}

void MaskPersistence::extend(cv::Mat& mask, const RgbdFrame& frame, const cv::Mat& flow) {
  const cv::Size size = frame.depth.size();
  if (mask.type() != CV_8UC1 || mask.size() != size || frame.depth.type() != CV_32FC1 ||
      frame.colour.type() != CV_8UC3 || frame.colour.size() != size)
    throw Error("MaskPersistence: expected a CV_8UC1 mask, CV_32FC1 depth and CV_8UC3 colour of one size");
  const bool has_previous = config_.enabled && !flow.empty() && previous_mask_.size() == size;
  if (has_previous && (flow.type() != CV_32FC2 || flow.size() != size))
    throw Error("MaskPersistence: expected a CV_32FC2 flow of the frame's size");
  if (has_previous) {
    const int colour_max = int(config_.colour_max);
    const cv::Rect box = searchBox(size);
    for (int y = box.y; y < box.y + box.height; ++y) {
      const float* d = frame.depth.ptr<float>(y);
      const cv::Vec2f* f = flow.ptr<cv::Vec2f>(y);
      const cv::Vec3b* c = frame.colour.ptr<cv::Vec3b>(y);
      std::uint8_t* m = mask.ptr<std::uint8_t>(y);
      for (int x = box.x; x < box.x + box.width; ++x) {
        // Positive and finite depth decided the pixel already.
        if (m[x] != 0 || ((d[x] > 0.0f) & (d[x] <= std::numeric_limits<float>::max()))) continue;
        const float fx = f[x][0], fy = f[x][1];
        if (!std::isfinite(fx) || !std::isfinite(fy)) continue;
        const int px = nearestPixel(float(x) + fx), py = nearestPixel(float(y) + fy);
        if (px < 0 || py < 0 || px >= size.width || py >= size.height) continue;
        if (previous_mask_.ptr<std::uint8_t>(py)[px] == 0) continue;
        const cv::Vec3b p = previous_colour_.ptr<cv::Vec3b>(py)[px];
        const int diff = std::abs(int(c[x][0]) - int(p[0])) + std::abs(int(c[x][1]) - int(p[1])) +
                         std::abs(int(c[x][2]) - int(p[2]));
        if (diff <= colour_max) m[x] = 255;
      }
    }
  }
  // The next frame reads the previous colour only where the previous mask is foreground: only the
  // mask's box is kept (the mask itself is kept whole, 0 outside the box).
  const cv::Rect box = cv::boundingRect(mask);
  if (previous_mask_.size() != size)
    previous_mask_ = cv::Mat::zeros(size, CV_8UC1);
  else if (!previous_box_.empty())
    previous_mask_(previous_box_).setTo(0);
  previous_colour_.create(size, CV_8UC3);
  if (!box.empty()) {
    mask(box).copyTo(previous_mask_(box));
    frame.colour(box).copyTo(previous_colour_(box));
  }
  previous_box_ = box;
}

}  // namespace holo::depthfilter
