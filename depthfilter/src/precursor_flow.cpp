#include "holo/depthfilter/precursor_flow.hpp"

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

cv::Mat PrecursorFlow::flowBetween(const cv::Mat& current, const cv::Mat& previous, const cv::Size& size) {
  cv::Mat flow;
  float scale = 1.0f;
  if (downscale_ == 1) {
    flow = cv::Mat::zeros(size, CV_32FC2);
    dis_->calc(current, previous, flow);
  } else {
    small_flow_ = cv::Mat::zeros(current.size(), CV_32FC2);
    dis_->calc(current, previous, small_flow_);
    cv::resize(small_flow_, flow, size, 0, 0, cv::INTER_LINEAR);  // writes every pixel
    scale = float(downscale_);
  }
  // To full-size pixels, and, in the same pass, DIS's rare non-finite vectors patched to 0 so
  // precursors stay indexable (one pass over the flow instead of a multiply and a patch).
  const int values = flow.cols * 2;
  for (int y = 0; y < flow.rows; ++y) {
    float* __restrict row = flow.ptr<float>(y);
    for (int i = 0; i < values; ++i) {
      const float v = row[i] * scale;
      row[i] = v == v ? v : 0.0f;  // NaN -> 0, as cv::patchNaNs
    }
  }
  if (round_trip_check_) rejectRoundTripFailures(current, previous, flow);
  return flow;
}

void PrecursorFlow::rejectRoundTripFailures(const cv::Mat& current, const cv::Mat& previous, cv::Mat& flow) {
  forward_flow_ = cv::Mat::zeros(current.size(), CV_32FC2);
  dis_->calc(previous, current, forward_flow_);
  // In the downscaled images' pixels, where both flows live.
  const float scale = 1.0f / float(downscale_);
  const float max_sq = (round_trip_max_px_ * scale) * (round_trip_max_px_ * scale);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const int w = forward_flow_.cols, h = forward_flow_.rows;
  for (int y = 0; y < flow.rows; ++y) {
    cv::Vec2f* row = flow.ptr<cv::Vec2f>(y);
    for (int x = 0; x < flow.cols; ++x) {
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
  return flowBetween(current_image_, previous_image_, current_bgr.size());
}

cv::Mat PrecursorFlow::next(const cv::Mat& current_bgr) {
  if (current_bgr.type() != CV_8UC3) throw Error("PrecursorFlow: expected a CV_8UC3 current frame");
  flowImage(current_bgr, current_image_);
  cv::Mat flow = previous_size_ == current_bgr.size()
                     ? flowBetween(current_image_, previous_image_, current_bgr.size())
                     : cv::Mat::zeros(current_bgr.size(), CV_32FC2);
  std::swap(current_image_, previous_image_);
  previous_size_ = current_bgr.size();
  return flow;
}

void PrecursorFlow::reset() {
  previous_size_ = {};
}

}  // namespace holo::depthfilter
