// A depth filter run over the synthetic sequence (synthetic_rgbd.hpp) with its true foreground
// mask, so that only the depth filter is measured: the static box's frame-to-frame change, the
// error on the moving disc and on the box, and how much of the foreground gets a depth. Shared by
// the depth filter's tests and the baselines' comparison with it.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <opencv2/imgproc.hpp>

#include "holo/depthfilter/precursor_flow.hpp"
#include "holo/depthfilter/temporal_depth_filter.hpp"
#include "synthetic_rgbd.hpp"

namespace holo::test {

using DepthFilterFn = std::function<cv::Mat(const depthfilter::DepthFilterInput&)>;

inline cv::Mat erodedMask(const cv::Mat& mask, int radius) {
  cv::Mat out;
  cv::erode(mask, out, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * radius + 1, 2 * radius + 1)));
  return out;
}

struct SyntheticRunMetrics {
  double temporal_mse_static_cm2 = 0.0;  // frame-to-frame change on the static box (cm^2)
  double rmse_disc_cm = 0.0;             // error against the truth on the moving disc
  double rmse_box_cm = 0.0;              // error against the truth on the static box
  double hole_fill = 0.0;                // share of foreground pixels with an output depth
};

// Runs `filter` over `frames` frames (after `skip` warm-up frames that are not scored), with the
// true foreground mask so that only the depth filter is measured.
inline SyntheticRunMetrics runOnSyntheticScene(const SyntheticScene& scene, const DepthFilterFn& filter,
                                               int skip, int frames) {
  depthfilter::PrecursorFlow flow;
  cv::Mat previous_colour, previous_out;
  SyntheticRunMetrics m;
  double temporal_sum = 0.0, disc_sum = 0.0, box_sum = 0.0;
  long temporal_n = 0, disc_n = 0, box_n = 0, filled = 0, foreground = 0;
  for (int t = 0; t < skip + frames; ++t) {
    const SyntheticFrame f = scene.render(t, 11);
    const cv::Mat lambda = flow.compute(f.frame.colour, previous_colour);
    previous_colour = f.frame.colour;
    const cv::Mat out = filter({f.frame.colour, f.frame.depth, f.true_mask, lambda});
    if (t >= skip) {
      const cv::Mat box = erodedMask(f.box_mask, 2), disc = erodedMask(f.disc_mask, 2),
                    fg = erodedMask(f.true_mask, 2);
      for (int y = 0; y < out.rows; ++y)
        for (int x = 0; x < out.cols; ++x) {
          const float d = out.at<float>(y, x), truth = f.true_depth.at<float>(y, x);
          if (fg.at<std::uint8_t>(y, x)) {
            ++foreground;
            filled += d > 0.0f;
          }
          if (!(d > 0.0f)) continue;
          const double e = 100.0 * (double(d) - truth);
          if (disc.at<std::uint8_t>(y, x)) disc_sum += e * e, ++disc_n;
          if (box.at<std::uint8_t>(y, x)) {
            box_sum += e * e, ++box_n;
            const float p = previous_out.empty() ? 0.0f : previous_out.at<float>(y, x);
            if (p > 0.0f && t > skip) {
              const double c = 100.0 * (double(d) - p);
              temporal_sum += c * c;
              ++temporal_n;
            }
          }
        }
    }
    previous_out = out;
  }
  m.temporal_mse_static_cm2 = temporal_sum / double(std::max(1L, temporal_n));
  m.rmse_disc_cm = std::sqrt(disc_sum / double(std::max(1L, disc_n)));
  m.rmse_box_cm = std::sqrt(box_sum / double(std::max(1L, box_n)));
  m.hole_fill = double(filled) / double(std::max(1L, foreground));
  return m;
}

inline cv::Mat rawDepthOnMask(const depthfilter::DepthFilterInput& in) {
  cv::Mat out = cv::Mat::zeros(in.depth.size(), CV_32FC1);
  in.depth.copyTo(out, in.mask);
  cv::patchNaNs(out, 0.0);
  return out;
}

inline depthfilter::TemporalDepthFilterConfig quickFilterConfig() {
  depthfilter::TemporalDepthFilterConfig config;
  config.learning_frames = 10;
  config.levels = 6;  // the 12x10 hole in the box needs l_max >= 5; edges here are simple
  return config;
}

}  // namespace holo::test
