#include "holo/eval/depth_baselines.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "holo/core/error.hpp"

namespace holo::eval {

namespace {

using depthfilter::DepthFilterInput;

cv::Mat sanitisedDepth(const cv::Mat& depth) {
  cv::Mat out = depth.clone();
  out.forEach<float>([](float& d, const int*) {
    if (!std::isfinite(d) || d < 0.0f) d = 0.0f;
  });
  return out;
}

void checkInput(const DepthFilterInput& in) {
  if (in.depth.type() != CV_32FC1 || in.mask.type() != CV_8UC1 || in.mask.size() != in.depth.size())
    throw Error("depth baseline filter: expected CV_32FC1 depth and a CV_8UC1 mask of one size");
}

}  // namespace

TemporalMedianDepthFilter::TemporalMedianDepthFilter(int window) : window_(window) {
  if (window < 1) throw Error("TemporalMedianDepthFilter: window must be >= 1");
}

cv::Mat TemporalMedianDepthFilter::apply(const DepthFilterInput& in) {
  checkInput(in);
  if (!history_.empty() && history_.back().size() != in.depth.size()) history_.clear();
  history_.push_back(sanitisedDepth(in.depth));
  while (static_cast<int>(history_.size()) > window_) history_.pop_front();
  cv::Mat out = cv::Mat::zeros(in.depth.size(), CV_32FC1);
  std::vector<float> values;
  for (int y = 0; y < out.rows; ++y)
    for (int x = 0; x < out.cols; ++x) {
      if (in.mask.at<std::uint8_t>(y, x) == 0) continue;
      values.clear();
      for (const cv::Mat& frame : history_)
        if (const float d = frame.at<float>(y, x); d > 0.0f) values.push_back(d);
      if (values.empty()) continue;
      const auto middle = values.begin() + std::ptrdiff_t(values.size() / 2);
      std::nth_element(values.begin(), middle, values.end());
      out.at<float>(y, x) = *middle;
    }
  return out;
}

TaaDepthFilter::TaaDepthFilter(float blend) : blend_(blend) {
  if (!(blend > 0.0f && blend <= 1.0f)) throw Error("TaaDepthFilter: blend must lie in (0, 1]");
}

cv::Mat TaaDepthFilter::apply(const DepthFilterInput& in) {
  checkInput(in);
  const cv::Mat depth = sanitisedDepth(in.depth);
  const bool has_flow = in.flow.type() == CV_32FC2 && in.flow.size() == depth.size();
  if (!history_.empty() && history_.size() != depth.size()) history_.release();
  cv::Mat out = cv::Mat::zeros(depth.size(), CV_32FC1);
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x) {
      if (in.mask.at<std::uint8_t>(y, x) == 0) continue;
      float lo = INFINITY, hi = 0.0f;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= depth.cols || ny >= depth.rows) continue;
          const float d = depth.at<float>(ny, nx);
          if (d <= 0.0f) continue;
          lo = std::min(lo, d);
          hi = std::max(hi, d);
        }
      float history = 0.0f;
      if (!history_.empty()) {
        int px = x, py = y;
        if (has_flow) {
          const cv::Vec2f f = in.flow.at<cv::Vec2f>(y, x);
          if (std::isfinite(f[0]) && std::isfinite(f[1])) {
            px = static_cast<int>(std::lround(float(x) + f[0]));
            py = static_cast<int>(std::lround(float(y) + f[1]));
          }
        }
        if (px >= 0 && py >= 0 && px < depth.cols && py < depth.rows) history = history_.at<float>(py, px);
      }
      const float current = depth.at<float>(y, x);
      if (hi <= 0.0f) {  // no valid neighbour: keep the history as it is
        out.at<float>(y, x) = history;
        continue;
      }
      if (history <= 0.0f) {
        out.at<float>(y, x) = current > 0.0f ? current : 0.5f * (lo + hi);
        continue;
      }
      history = std::clamp(history, lo, hi);
      out.at<float>(y, x) = current > 0.0f ? blend_ * current + (1.0f - blend_) * history : history;
    }
  history_ = out.clone();
  return out;
}

}  // namespace holo::eval
