#include "holo/depthfilter/precursor_flow.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"

namespace holo::depthfilter {

PrecursorFlow::PrecursorFlow(PrecursorFlowConfig config) : dis_(cv::DISOpticalFlow::create(config.preset)) {}

cv::Mat PrecursorFlow::compute(const cv::Mat& current_bgr, const cv::Mat& previous_bgr) {
  if (current_bgr.type() != CV_8UC3) throw Error("PrecursorFlow: expected a CV_8UC3 current frame");
  cv::Mat flow = cv::Mat::zeros(current_bgr.size(), CV_32FC2);
  if (previous_bgr.empty() || previous_bgr.size() != current_bgr.size()) return flow;
  cv::Mat current_grey, previous_grey;
  cv::cvtColor(current_bgr, current_grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(previous_bgr, previous_grey, cv::COLOR_BGR2GRAY);
  dis_->calc(current_grey, previous_grey, flow);
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
