// The displayed flicker of the relic's foreground reflection: how much the pixels a visitor sees
// on the relic change from frame to frame where visitors reflect, against the change the truth
// shows (the same renderer fed the true depth), with what a method leaves out counted as error.
//
// For consecutive frames i-1, i of each face view and each pixel p where the truth or the method
// shows a visitor in either frame (foreground weight w > 0), with D the displayed sRGB levels
// (0..255, mean over the three channels of the squares) and e = D_method - D_truth:
//   temporal  |e_i(p) - e_{i-1}(p)|^2: the method's change beyond the truth's own (0 for a method
//             that changes exactly as the truth does, whatever its constant error);
//   missing   max(0, w_truth,i(p) - w_method,i(p)) |e_i(p)|^2: the reflection the truth shows and
//             the method does not, at its full displayed error. To a visitor a missing reflection
//             is the reflection switched off; without this term a method that drops the visitors'
//             reflection would pay only the truth's own change and could beat one that shows it.
// A pair's flicker is the sum of both over those pixels divided by the number of pixels where the
// truth shows a visitor in either frame (so a method cannot dilute its error by spreading
// reflection where there is none); pairs without any are not scored. The figure is the mean over
// the scored pairs. Units: squared 8-bit display levels.
#pragma once

#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace holo::eval {

// One frame as displayed: per face view its sRGB image and its foreground weight.
struct DisplayedFrame {
  std::vector<cv::Mat> display;  // CV_8UC3 sRGB BGR, one per view
  std::vector<cv::Mat> weight;   // CV_32FC1 [0, 1], the visitors' share of each pixel's reflection
};

struct ReflectionFlickerMetrics {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double flicker = kNaN;   // levels^2, mean over the scored pairs of (temporal + missing) per pixel
  double temporal = kNaN;  // its temporal part alone
  double missing = kNaN;   // its missing part alone
  // Of the truth's reflection weight over the scored frames, the share the method does not show
  // (sum of max(0, w_truth - w_method) over sum of w_truth).
  double missing_share = kNaN;
  // The literal change |D_i - D_{i-1}|^2 of the method's own display over the same pixels and
  // denominator: a diagnostic (the truth's value is the visitors' real motion).
  double displayed_change = kNaN;
  std::vector<double> per_pair;  // each pair's flicker, NaN where nothing was scored
  long scored_pairs = 0;
};

// Accumulates the flicker of one method over consecutive frames.
class ReflectionFlickerScorer {
 public:
  // `method` and `truth` are the same frame, with the same views and sizes. Throws holo::Error
  // otherwise.
  void add(const DisplayedFrame& method, const DisplayedFrame& truth);
  ReflectionFlickerMetrics metrics() const;

 private:
  struct Pair {
    double temporal = 0.0, missing = 0.0, change = 0.0;
    long truth_pixels = 0;
  };
  std::vector<Pair> pairs_;
  double missing_weight_ = 0.0, truth_weight_ = 0.0;
  DisplayedFrame previous_method_, previous_truth_;
};

// A Markdown table of the metrics, one row per (name, metrics); NaN prints as "n/a".
std::string reflectionFlickerTable(std::span<const std::pair<std::string, ReflectionFlickerMetrics>> rows);

}  // namespace holo::eval
