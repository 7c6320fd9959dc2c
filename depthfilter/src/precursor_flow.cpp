#include "holo/depthfilter/precursor_flow.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::depthfilter {

PrecursorFlow::PrecursorFlow(PrecursorFlowConfig config)
    : dis_(cv::DISOpticalFlow::create(config.preset)), downscale_(config.downscale) {
  if (downscale_ < 1) throw Error("PrecursorFlow: downscale must be >= 1");
}

cv::Mat PrecursorFlow::compute(const cv::Mat& current_bgr, const cv::Mat& previous_bgr) {
  if (current_bgr.type() != CV_8UC3) throw Error("PrecursorFlow: expected a CV_8UC3 current frame");
  cv::Mat flow = cv::Mat::zeros(current_bgr.size(), CV_32FC2);
  if (previous_bgr.empty() || previous_bgr.size() != current_bgr.size()) return flow;
  cv::cvtColor(current_bgr, current_grey_, cv::COLOR_BGR2GRAY);
  cv::cvtColor(previous_bgr, previous_grey_, cv::COLOR_BGR2GRAY);
  if (downscale_ == 1) {
    dis_->calc(current_grey_, previous_grey_, flow);
  } else {
    const cv::Size small((current_bgr.cols + downscale_ - 1) / downscale_,
                         (current_bgr.rows + downscale_ - 1) / downscale_);
    cv::resize(current_grey_, small_current_, small, 0, 0, cv::INTER_AREA);
    cv::resize(previous_grey_, small_previous_, small, 0, 0, cv::INTER_AREA);
    small_flow_ = cv::Mat::zeros(small, CV_32FC2);
    dis_->calc(small_current_, small_previous_, small_flow_);
    cv::resize(small_flow_, flow, current_bgr.size(), 0, 0, cv::INTER_LINEAR);
    flow *= double(downscale_);
  }
  // DIS keeps flow finite on valid images; patch anything else so precursors stay indexable.
  cv::patchNaNs(flow, 0.0);
  return flow;
}

float precursorConfidence(const cv::Vec3b& pixel, const cv::Vec3b& precursor) {
  float sum = 0.0f;
  for (int c = 0; c < 3; ++c) {
    const float diff = float(pixel[c]) - float(precursor[c]);
    sum += diff * diff;
  }
  return std::sqrt(sum);
}

}  // namespace holo::depthfilter
