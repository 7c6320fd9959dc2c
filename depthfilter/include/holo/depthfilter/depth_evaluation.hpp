// Evaluation of the temporal depth filter against its baselines on sequences with known truth
// (paper Sec. 4.1.3, Table 2; `holopyramid eval depth`). Every method sees the same
// foreground mask (ForegroundMasker) and the same precursor flow; frames are scored once our
// filter has finished learning its PDFs. Metrics per method, over one or more camera streams:
//   temporal_mse_cm2  the paper's MSE' (Equation 2) of the depth error e = d - d_true: mean over
//                     consecutive frame pairs of the mean of (e_i - e_{i-1})^2 (cm^2) over pixels
//                     that have an output and are truly foreground in both frames. On static
//                     content this is exactly the paper's frame-to-frame depth change; with
//                     walking visitors it leaves out their real motion, which the literal change
//                     cannot (docs/depthfilter.md, "Temporal MSE' with walking visitors");
//   depth_change_cm2  the literal frame-to-frame change (d_i - d_{i-1})^2 on the same pixels, real
//                     motion included; reported with the truth's own value as its floor;
//   depth_rmse_cm     RMS error against the true depth over the output pixels that truly are
//                     foreground (a filter that freezes or smears depth loses here);
//   hole_fill_ratio   share of pixels foreground in both truth and mask that get a depth (the
//                     output's coverage of the true foreground: a filter gains by filling holes
//                     and loses by dropping measurements; fills outside the true foreground
//                     count as ghosts, never as fills);
//   raw_holes_filled  of those pixels, the ones the sensor gave no depth: the share that gets one
//                     (raw: 0). Reported beside the bar, which is on hole_fill_ratio;
//   ghost_ratio       share of output pixels where the truth has no foreground (trails);
//   ms_per_frame      wall time of the method's depth filtering alone, per frame.
#pragma once

#include <array>
#include <span>
#include <string>

#include "holo/core/rgbd_frame.hpp"
#include "holo/depthfilter/depth_baselines.hpp"
#include "holo/depthfilter/foreground_mask.hpp"
#include "holo/depthfilter/precursor_flow.hpp"
#include "holo/depthfilter/temporal_depth_filter.hpp"

namespace holo::depthfilter {

enum class DepthMethod { Ours = 0, Raw, Median, Taa };
inline constexpr std::array<DepthMethod, 4> kDepthMethods{DepthMethod::Ours, DepthMethod::Raw,
                                                          DepthMethod::Median, DepthMethod::Taa};
const char* depthMethodName(DepthMethod method);  // "ours", "raw", "median", "taa"

struct GroundTruthFrame {
  RgbdFrame frame;          // as the sensor delivers it
  cv::Mat true_depth;       // CV_32FC1 metres
  cv::Mat true_foreground;  // CV_8UC1, non-zero = truly foreground
};

struct DepthMethodMetrics {
  double temporal_mse_cm2 = 0.0;
  double depth_change_cm2 = 0.0;
  double depth_rmse_cm = 0.0;
  double hole_fill_ratio = 0.0;
  double raw_holes_filled = 0.0;
  double ghost_ratio = 0.0;
  double ms_per_frame = 0.0;
  long scored_frames = 0;
};

// Accumulates the metrics above for one method on one camera stream, frame by frame. Usable on
// its own to score any filter (tests score frozen and over-smoothed filters with it).
class DepthScorer {
 public:
  // output: CV_32FC1 metres (0 = none); mask: the foreground mask the method saw; truth: the
  // frame's true depth and true foreground. `seconds` is the method's time on this frame.
  void add(const cv::Mat& output, const cv::Mat& mask, const GroundTruthFrame& truth, double seconds = 0.0);
  DepthMethodMetrics metrics() const;
  // Pools the sums of several streams (not an average of averages).
  void merge(const DepthScorer& other);

 private:
  double error_change_sum_ = 0.0;  // sum over frame pairs of that pair's mean (e_i - e_{i-1})^2
  double depth_change_sum_ = 0.0;  // same for (d_i - d_{i-1})^2
  long pairs_ = 0;
  double error_sq_sum_ = 0.0;
  long error_n_ = 0;
  long fill_hits_ = 0, fill_n_ = 0;
  long raw_holes_filled_ = 0, raw_holes_ = 0;  // of fill_n_, pixels without a measured depth
  long ghosts_ = 0, outputs_ = 0;
  double seconds_ = 0.0;
  long frames_ = 0;
  cv::Mat previous_output_, previous_true_depth_, previous_true_foreground_;
};

struct DepthEvaluationConfig {
  ForegroundMaskConfig mask;
  PrecursorFlowConfig flow;
  TemporalDepthFilterConfig filter;
  int median_window = 5;
  float taa_blend = 0.1f;
};

// One camera stream. Not thread-safe; use one per camera.
class DepthFilterEvaluation {
 public:
  explicit DepthFilterEvaluation(DepthEvaluationConfig config = {});

  void learnBackground(const RgbdFrame& background);
  // Runs every method on the frame and scores it once our filter has stopped learning.
  void addFrame(const GroundTruthFrame& frame);

  DepthMethodMetrics metrics(DepthMethod method) const;
  // Metrics over several camera streams (sums pooled, not averages of averages).
  static DepthMethodMetrics combined(std::span<const DepthFilterEvaluation> streams, DepthMethod method);

  const cv::Mat& lastOutput(DepthMethod method) const { return methods_[std::size_t(method)].last_output; }
  const cv::Mat& lastMask() const { return last_mask_; }
  bool learning() const { return ours_.learning(); }
  // The literal frame-to-frame change of the true depth itself on the mask: the floor of
  // depth_change_cm2 for any filter that does not freeze.
  DepthMethodMetrics truthMetrics() const { return truth_.scorer.metrics(); }
  static DepthMethodMetrics combinedTruth(std::span<const DepthFilterEvaluation> streams);

 private:
  struct MethodState {
    DepthScorer scorer;
    cv::Mat last_output;
  };

  ForegroundMasker masker_;
  PrecursorFlow flow_;
  TemporalDepthFilter ours_;
  TemporalMedianDepthFilter median_;
  TaaDepthFilter taa_;
  cv::Mat previous_color_;
  cv::Mat last_mask_;
  std::array<MethodState, 4> methods_;
  MethodState truth_;
};

}  // namespace holo::depthfilter
