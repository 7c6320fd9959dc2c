// Where ours' coverage goes: every true visitor pixel of a scored frame classed by what became of
// it. Covered (ours output a depth); outside the mask (the sensor read it within the background's
// depth margin, clearly in front of the background, where the mask has learned no background
// depth, or read nothing); or a hole inside the
// mask, by the filter's reason for leaving it (depthfilter::HoleReason) and whether the sensor
// read nothing there or read a depth the filter dropped as a flying pixel. Shares are of the true
// visitor pixels and sum to 1.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "holo/depthfilter/foreground_mask.hpp"
#include "holo/depthfilter/hole_reason.hpp"

namespace holo::eval {

struct CoverageBreakdownFrame {
  const cv::Mat& true_foreground;   // CV_8UC1, non-zero = a visitor
  const cv::Mat& true_depth;        // CV_32FC1 metres (0 = no visitor depth)
  const cv::Mat& sensor_depth;      // CV_32FC1 metres as the sensor read it (0/NaN = nothing)
  const cv::Mat& background_depth;  // CV_32FC1 metres, the mask's learned background (0 = unknown)
  const cv::Mat& mask;              // CV_8UC1, ours' foreground mask
  const cv::Mat& output;            // CV_32FC1, ours' depth
  const cv::Mat& hole_reasons;      // CV_8UC1 depthfilter::HoleReason per pixel
};

class CoverageBreakdown {
 public:
  // `margin` gives the mask's depth margin (ForegroundMaskConfig::depth_margin_*).
  explicit CoverageBreakdown(const depthfilter::ForegroundMaskConfig& margin);
  // Throws holo::Error when the images' types or sizes disagree.
  void add(const CoverageBreakdownFrame& frame);
  void merge(const CoverageBreakdown& other);

  long visitorPixels() const { return visitor_pixels_; }
  double covered() const { return share(covered_); }
  double outsideWithinMargin() const { return share(outside_within_margin_); }
  double outsideInFront() const { return share(outside_in_front_); }
  double outsideUnknownBackground() const { return share(outside_unknown_background_); }
  double outsideNoDepth() const { return share(outside_no_depth_); }
  // Holes inside the mask with `reason`: the sensor read nothing / read a depth the filter dropped.
  double hole(depthfilter::HoleReason reason, bool sensor_read) const;
  double holes() const;  // all of them

  nlohmann::json toJson() const;
  std::string table() const;  // Markdown

 private:
  double share(long n) const { return visitor_pixels_ > 0 ? double(n) / double(visitor_pixels_) : 0.0; }
  static constexpr std::size_t kReasons = depthfilter::kHoleReasons.size() + 1;  // None included
  float margin_m_, margin_z2_;
  long visitor_pixels_ = 0, covered_ = 0;
  long outside_within_margin_ = 0, outside_in_front_ = 0, outside_unknown_background_ = 0,
       outside_no_depth_ = 0;
  std::array<std::array<long, 2>, kReasons> holes_{};  // [reason][sensor read]
};

}  // namespace holo::eval
