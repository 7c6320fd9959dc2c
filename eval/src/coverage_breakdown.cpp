#include "holo/eval/coverage_breakdown.hpp"

#include <cmath>
#include <cstdio>

#include "holo/core/error.hpp"

namespace holo::eval {

using depthfilter::HoleReason;

CoverageBreakdown::CoverageBreakdown(const depthfilter::ForegroundMaskConfig& margin)
    : margin_m_(margin.depth_margin_m), margin_z2_(margin.depth_margin_z2) {}

void CoverageBreakdown::add(const CoverageBreakdownFrame& f) {
  const cv::Size size = f.true_foreground.size();
  const auto matches = [&](const cv::Mat& m, int type) { return m.type() == type && m.size() == size; };
  if (!matches(f.true_foreground, CV_8UC1) || !matches(f.true_depth, CV_32FC1) ||
      !matches(f.sensor_depth, CV_32FC1) || !matches(f.background_depth, CV_32FC1) ||
      !matches(f.mask, CV_8UC1) || !matches(f.output, CV_32FC1) || !matches(f.hole_reasons, CV_8UC1))
    throw Error(
        "CoverageBreakdown: expected CV_8UC1 true foreground, mask and hole reasons and CV_32FC1 true, "
        "sensor, background and output depth, all of one size");
  for (int y = 0; y < size.height; ++y) {
    const std::uint8_t* tf = f.true_foreground.ptr<std::uint8_t>(y);
    const float* td = f.true_depth.ptr<float>(y);
    const float* raw = f.sensor_depth.ptr<float>(y);
    const float* bg = f.background_depth.ptr<float>(y);
    const std::uint8_t* mask = f.mask.ptr<std::uint8_t>(y);
    const float* out = f.output.ptr<float>(y);
    const std::uint8_t* reason = f.hole_reasons.ptr<std::uint8_t>(y);
    for (int x = 0; x < size.width; ++x) {
      if (!(tf[x] && td[x] > 0.0f)) continue;  // the scorer's visitor pixels
      ++visitor_pixels_;
      const bool read = std::isfinite(raw[x]) && raw[x] > 0.0f;
      if (out[x] > 0.0f) {
        ++covered_;
      } else if (mask[x] == 0) {
        if (!read)
          ++outside_no_depth_;
        else if (!(bg[x] > 0.0f))
          ++outside_unknown_background_;
        else if (raw[x] >= bg[x] - (margin_m_ + margin_z2_ * bg[x] * bg[x]))
          ++outside_within_margin_;
        else
          ++outside_in_front_;
      } else {
        const std::size_t r = reason[x] < kReasons ? reason[x] : 0;
        ++holes_[r][read ? 1 : 0];
      }
    }
  }
}

void CoverageBreakdown::merge(const CoverageBreakdown& o) {
  visitor_pixels_ += o.visitor_pixels_;
  covered_ += o.covered_;
  outside_within_margin_ += o.outside_within_margin_;
  outside_in_front_ += o.outside_in_front_;
  outside_unknown_background_ += o.outside_unknown_background_;
  outside_no_depth_ += o.outside_no_depth_;
  for (std::size_t r = 0; r < kReasons; ++r)
    for (std::size_t s = 0; s < 2; ++s) holes_[r][s] += o.holes_[r][s];
}

double CoverageBreakdown::hole(HoleReason reason, bool sensor_read) const {
  return share(holes_[std::size_t(reason)][sensor_read ? 1 : 0]);
}

double CoverageBreakdown::holes() const {
  long n = 0;
  for (const auto& h : holes_) n += h[0] + h[1];
  return share(n);
}

nlohmann::json CoverageBreakdown::toJson() const {
  nlohmann::json holes;
  for (std::size_t r = 0; r < kReasons; ++r) {
    if (holes_[r][0] + holes_[r][1] == 0) continue;
    holes[depthfilter::holeReasonName(HoleReason(r))] = {{"sensor_read_nothing", share(holes_[r][0])},
                                                         {"flying_pixel_dropped", share(holes_[r][1])}};
  }
  return {{"visitor_pixels", visitor_pixels_},
          {"covered", covered()},
          {"outside_mask_within_background_margin", outsideWithinMargin()},
          {"outside_mask_in_front_of_background", outsideInFront()},
          {"outside_mask_background_depth_unknown", outsideUnknownBackground()},
          {"outside_mask_no_depth", outsideNoDepth()},
          {"holes_inside_mask", this->holes()},
          {"holes_by_reason", holes}};
}

std::string CoverageBreakdown::table() const {
  const auto percent = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f%%", 100.0 * v);
    return std::string(text);
  };
  std::string t =
      "| ours' true visitor pixels | share | sensor read nothing | sensor read, dropped as flying |\n"
      "|---|---|---|---|\n";
  t += "| covered | " + percent(covered()) + " | | |\n";
  t += "| outside the mask, depth within the background's margin | " + percent(outsideWithinMargin()) +
       " | | |\n";
  t += "| outside the mask, depth in front of the background | " + percent(outsideInFront()) + " | | |\n";
  t += "| outside the mask, depth where the background's is unknown | " +
       percent(outsideUnknownBackground()) + " | | |\n";
  t += "| outside the mask, no depth | " + percent(outsideNoDepth()) + " | | |\n";
  t += "| holes inside the mask | " + percent(holes()) + " | | |\n";
  for (std::size_t r = 0; r < kReasons; ++r) {
    if (holes_[r][0] + holes_[r][1] == 0) continue;
    t += "| hole: " + std::string(depthfilter::holeReasonName(HoleReason(r))) + " | " +
         percent(share(holes_[r][0] + holes_[r][1])) + " | " + percent(share(holes_[r][0])) + " | " +
         percent(share(holes_[r][1])) + " |\n";
  }
  return t;
}

}  // namespace holo::eval
