#include "holo/depthfilter/precursor_flow.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::depthfilter {

PrecursorFlow::PrecursorFlow(PrecursorFlowConfig config)
    : dis_(cv::DISOpticalFlow::create(config.preset)),
      downscale_(config.downscale),
      round_trip_check_(config.round_trip_check),
      round_trip_max_px_(config.round_trip_max_px) {
  if (downscale_ < 1) throw Error("PrecursorFlow: downscale must be >= 1");
  if (!(round_trip_max_px_ >= 0.0f)) throw Error("PrecursorFlow: round_trip_max_px must be >= 0");
}

void PrecursorFlow::flowImage(const cv::Mat& bgr, cv::Mat& out) {
  if (downscale_ == 1) {
    cv::cvtColor(bgr, out, cv::COLOR_BGR2GRAY);
    return;
  }
  cv::cvtColor(bgr, grey_, cv::COLOR_BGR2GRAY);
  const cv::Size small((bgr.cols + downscale_ - 1) / downscale_, (bgr.rows + downscale_ - 1) / downscale_);
  cv::resize(grey_, out, small, 0, 0, cv::INTER_AREA);
}

void PrecursorFlow::upsampleInside(const cv::Rect& needed, cv::Mat& flow) {
  // A whole-frame resize maps full-size pixel x to small-image x / 2 - 1/4 and clamps at the
  // frame's edges. Resizing a block of the small flow by exactly 2 gives each full-size pixel the
  // same two weights and neighbours, except the block's outermost pixel on a side where the block
  // does not reach the frame's edge (clamped there instead): one small pixel more on each side
  // keeps those outside `needed`.
  const cv::Size small = small_flow_.size();
  const int x0 = std::max(0, needed.x / 2 - 1), y0 = std::max(0, needed.y / 2 - 1);
  const int x1 = std::min(small.width, (needed.x + needed.width + 1) / 2 + 1);
  const int y1 = std::min(small.height, (needed.y + needed.height + 1) / 2 + 1);
  const cv::Rect block(x0, y0, x1 - x0, y1 - y0);
  cv::resize(small_flow_(block), upsampled_block_, block.size() * 2, 0, 0, cv::INTER_LINEAR);
  upsampled_block_(needed - cv::Point(2 * x0, 2 * y0)).copyTo(flow(needed));
}

cv::Mat PrecursorFlow::flowBetween(const cv::Mat& current, const cv::Mat& previous, const cv::Size& size,
                                   const cv::Rect& needed) {
  const cv::Rect frame(0, 0, size.width, size.height);
  cv::Rect inside = needed & frame;
  if (inside.empty()) return cv::Mat::zeros(size, CV_32FC2);
  cv::Mat flow;
  float scale = 1.0f;
  if (downscale_ == 1) {
    flow = cv::Mat::zeros(size, CV_32FC2);
    dis_->calc(current, previous, flow);
  } else {
    small_flow_ = cv::Mat::zeros(current.size(), CV_32FC2);  // DIS starts from a flow of its size
    dis_->calc(current, previous, small_flow_);
    // Exactly twice the small flow's size: a block resized by 2 matches the whole frame's resize.
    if (downscale_ == 2 && current.size() * 2 == size && inside != frame) {
      flow = upsampled_flow_.next(size, CV_32FC2);
      upsampleInside(inside, flow);
      upsampled_flow_.written(inside);  // the scaling and the round-trip check stay inside too
    } else {
      cv::resize(small_flow_, flow, size, 0, 0, cv::INTER_LINEAR);  // writes every pixel
      inside = frame;
    }
    scale = float(downscale_);
  }
  // To full-size pixels, and, in the same pass, DIS's rare non-finite vectors patched to 0 so
  // precursors stay indexable (one pass over the flow instead of a multiply and a patch).
  const int values = inside.width * 2;
  for (int y = inside.y; y < inside.y + inside.height; ++y) {
    float* __restrict row = flow.ptr<float>(y) + 2 * inside.x;
    for (int i = 0; i < values; ++i) {
      const float v = row[i] * scale;
      row[i] = v == v ? v : 0.0f;  // NaN -> 0, as cv::patchNaNs
    }
  }
  if (round_trip_check_) rejectRoundTripFailures(current, previous, inside, flow);
  return flow;
}

void PrecursorFlow::rejectRoundTripFailures(const cv::Mat& current, const cv::Mat& previous,
                                            const cv::Rect& needed, cv::Mat& flow) {
  forward_flow_ = cv::Mat::zeros(current.size(), CV_32FC2);
  dis_->calc(previous, current, forward_flow_);
  // In the downscaled images' pixels, where both flows live.
  const float scale = 1.0f / float(downscale_);
  const float max_sq = (round_trip_max_px_ * scale) * (round_trip_max_px_ * scale);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const int w = forward_flow_.cols, h = forward_flow_.rows;
  for (int y = needed.y; y < needed.y + needed.height; ++y) {
    cv::Vec2f* row = flow.ptr<cv::Vec2f>(y);
    for (int x = needed.x; x < needed.x + needed.width; ++x) {
      const cv::Vec2f back = row[x] * scale;
      const float sx = (float(x) + 0.5f) * scale - 0.5f, sy = (float(y) + 0.5f) * scale - 0.5f;
      const int qx = int(std::lround(sx + back[0])), qy = int(std::lround(sy + back[1]));
      if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;  // leaves the frame: the filter ignores it
      const cv::Vec2f forward = forward_flow_.at<cv::Vec2f>(qy, qx);
      const float ex = back[0] + forward[0], ey = back[1] + forward[1];
      if (!(ex * ex + ey * ey <= max_sq)) row[x] = cv::Vec2f(nan, nan);
    }
  }
}

cv::Mat PrecursorFlow::compute(const cv::Mat& current_bgr, const cv::Mat& previous_bgr) {
  if (current_bgr.type() != CV_8UC3) throw Error("PrecursorFlow: expected a CV_8UC3 current frame");
  if (previous_bgr.empty() || previous_bgr.size() != current_bgr.size())
    return cv::Mat::zeros(current_bgr.size(), CV_32FC2);
  flowImage(current_bgr, current_image_);
  flowImage(previous_bgr, previous_image_);
  previous_size_ = {};  // previous_image_ is not next()'s previous frame any more
  return flowBetween(current_image_, previous_image_, current_bgr.size(),
                     cv::Rect(0, 0, current_bgr.cols, current_bgr.rows));
}

cv::Mat PrecursorFlow::next(const cv::Mat& current_bgr) {
  return nextFlow(current_bgr, cv::Rect(0, 0, current_bgr.cols, current_bgr.rows));
}

cv::Mat PrecursorFlow::next(const cv::Mat& current_bgr, const cv::Rect& needed) {
  return nextFlow(current_bgr, needed);
}

cv::Mat PrecursorFlow::nextFlow(const cv::Mat& current_bgr, const cv::Rect& needed) {
  if (current_bgr.type() != CV_8UC3) throw Error("PrecursorFlow: expected a CV_8UC3 current frame");
  flowImage(current_bgr, current_image_);
  cv::Mat flow = previous_size_ == current_bgr.size()
                     ? flowBetween(current_image_, previous_image_, current_bgr.size(), needed)
                     : cv::Mat::zeros(current_bgr.size(), CV_32FC2);
  std::swap(current_image_, previous_image_);
  previous_size_ = current_bgr.size();
  return flow;
}

void PrecursorFlow::reset() {
  previous_size_ = {};
}

}  // namespace holo::depthfilter
