#include "holo/depthfilter/depth_evaluation.hpp"

#include <chrono>
#include <cmath>

#include "holo/core/error.hpp"

namespace holo::depthfilter {

const char* depthMethodName(DepthMethod method) {
  switch (method) {
    case DepthMethod::Ours:
      return "ours";
    case DepthMethod::Raw:
      return "raw";
    case DepthMethod::Median:
      return "median";
    case DepthMethod::Taa:
      return "taa";
  }
  return "?";
}

DepthFilterEvaluation::DepthFilterEvaluation(DepthEvaluationConfig config)
    : masker_(config.mask),
      flow_(config.flow),
      ours_(config.filter),
      median_(config.median_window),
      taa_(config.taa_blend) {}

void DepthFilterEvaluation::learnBackground(const RgbdFrame& background) {
  masker_.learnBackground(background);
}

void DepthScorer::add(const cv::Mat& out, const cv::Mat& mask, const GroundTruthFrame& truth,
                      double seconds) {
  if (out.type() != CV_32FC1 || out.size() != truth.true_depth.size() || mask.type() != CV_8UC1 ||
      mask.size() != out.size() || truth.frame.depth.type() != CV_32FC1 ||
      truth.frame.depth.size() != out.size())
    throw Error(
        "DepthScorer: expected a CV_32FC1 output, a CV_8UC1 mask and a CV_32FC1 measured depth of the true "
        "depth's "
        "size");
  seconds_ += seconds;
  ++frames_;
  const bool has_previous = !previous_output_.empty() && previous_output_.size() == out.size();
  double error_change = 0.0, depth_change = 0.0;
  long changes = 0;
  for (int y = 0; y < out.rows; ++y) {
    const float* d = out.ptr<float>(y);
    const float* td = truth.true_depth.ptr<float>(y);
    const std::uint8_t* tf = truth.true_foreground.ptr<std::uint8_t>(y);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(y);
    const float* raw = truth.frame.depth.ptr<float>(y);
    const float* prev = has_previous ? previous_output_.ptr<float>(y) : nullptr;
    const float* prev_td = has_previous ? previous_true_depth_.ptr<float>(y) : nullptr;
    const std::uint8_t* prev_tf = has_previous ? previous_true_foreground_.ptr<std::uint8_t>(y) : nullptr;
    for (int x = 0; x < out.cols; ++x) {
      const bool has = d[x] > 0.0f;
      if (tf[x] && m[x]) {
        ++fill_n_;
        fill_hits_ += has;
        if (!(std::isfinite(raw[x]) && raw[x] > 0.0f)) {
          ++raw_holes_;
          raw_holes_filled_ += has;
        }
      }
      if (!has) continue;
      ++outputs_;
      if (!tf[x]) {
        ++ghosts_;
        continue;
      }
      if (!(td[x] > 0.0f)) continue;
      const double e = 100.0 * (double(d[x]) - td[x]);
      error_sq_sum_ += e * e;
      ++error_n_;
      if (prev && prev[x] > 0.0f && prev_tf[x] && prev_td[x] > 0.0f) {
        const double c = 100.0 * (double(d[x]) - prev[x]);
        const double ce = e - 100.0 * (double(prev[x]) - prev_td[x]);
        depth_change += c * c;
        error_change += ce * ce;
        ++changes;
      }
    }
  }
  if (changes > 0) {
    depth_change_sum_ += depth_change / double(changes);
    error_change_sum_ += error_change / double(changes);
    ++pairs_;
  }
  previous_output_ = out.clone();
  previous_true_depth_ = truth.true_depth.clone();
  previous_true_foreground_ = truth.true_foreground.clone();
}

DepthMethodMetrics DepthScorer::metrics() const {
  DepthMethodMetrics m;
  m.temporal_mse_cm2 = pairs_ > 0 ? error_change_sum_ / double(pairs_) : 0.0;
  m.depth_change_cm2 = pairs_ > 0 ? depth_change_sum_ / double(pairs_) : 0.0;
  m.depth_rmse_cm = error_n_ > 0 ? std::sqrt(error_sq_sum_ / double(error_n_)) : 0.0;
  m.hole_fill_ratio = fill_n_ > 0 ? double(fill_hits_) / double(fill_n_) : 1.0;
  m.raw_holes_filled = raw_holes_ > 0 ? double(raw_holes_filled_) / double(raw_holes_) : 1.0;
  m.ghost_ratio = outputs_ > 0 ? double(ghosts_) / double(outputs_) : 0.0;
  m.ms_per_frame = frames_ > 0 ? 1000.0 * seconds_ / double(frames_) : 0.0;
  m.scored_frames = frames_;
  return m;
}

void DepthScorer::merge(const DepthScorer& o) {
  error_change_sum_ += o.error_change_sum_;
  depth_change_sum_ += o.depth_change_sum_;
  pairs_ += o.pairs_;
  error_sq_sum_ += o.error_sq_sum_;
  error_n_ += o.error_n_;
  fill_hits_ += o.fill_hits_;
  fill_n_ += o.fill_n_;
  raw_holes_filled_ += o.raw_holes_filled_;
  raw_holes_ += o.raw_holes_;
  ghosts_ += o.ghosts_;
  outputs_ += o.outputs_;
  seconds_ += o.seconds_;
  frames_ += o.frames_;
}

void DepthFilterEvaluation::addFrame(const GroundTruthFrame& truth) {
  const RgbdFrame& frame = truth.frame;
  if (truth.true_depth.type() != CV_32FC1 || truth.true_depth.size() != frame.depth.size() ||
      truth.true_foreground.type() != CV_8UC1 || truth.true_foreground.size() != frame.depth.size())
    throw Error(
        "DepthFilterEvaluation: expected true depth CV_32FC1 and true foreground CV_8UC1 of the frame's "
        "size");
  last_mask_ = masker_.apply(frame);
  const cv::Mat flow = flow_.compute(frame.color, previous_color_);
  previous_color_ = frame.color.clone();
  const DepthFilterInput input{frame.color, frame.depth, last_mask_, flow};
  const bool score = !ours_.learning();  // decided before this frame, like the filter itself

  for (DepthMethod method : kDepthMethods) {
    MethodState& state = methods_[std::size_t(method)];
    const auto start = std::chrono::steady_clock::now();
    cv::Mat out;
    switch (method) {
      case DepthMethod::Ours:
        out = ours_.apply(input);
        break;
      case DepthMethod::Raw:
        out = cv::Mat::zeros(frame.depth.size(), CV_32FC1);
        frame.depth.copyTo(out, last_mask_);
        out.forEach<float>([](float& d, const int*) {
          if (!std::isfinite(d) || d < 0.0f) d = 0.0f;
        });
        break;
      case DepthMethod::Median:
        out = median_.apply(input);
        break;
      case DepthMethod::Taa:
        out = taa_.apply(input);
        break;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (score) state.scorer.add(out, last_mask_, truth, seconds);
    state.last_output = out;
  }
  if (score) {
    cv::Mat true_output = cv::Mat::zeros(frame.depth.size(), CV_32FC1);
    truth.true_depth.copyTo(true_output, last_mask_ & truth.true_foreground);
    truth_.scorer.add(true_output, last_mask_, truth);
    truth_.last_output = true_output;
  }
}

DepthMethodMetrics DepthFilterEvaluation::metrics(DepthMethod method) const {
  return methods_[std::size_t(method)].scorer.metrics();
}

DepthMethodMetrics DepthFilterEvaluation::combined(std::span<const DepthFilterEvaluation> streams,
                                                   DepthMethod method) {
  DepthScorer total;
  for (const DepthFilterEvaluation& e : streams) total.merge(e.methods_[std::size_t(method)].scorer);
  // Frames are counted per stream; time per frame is per camera frame.
  return total.metrics();
}

DepthMethodMetrics DepthFilterEvaluation::combinedTruth(std::span<const DepthFilterEvaluation> streams) {
  DepthScorer total;
  for (const DepthFilterEvaluation& e : streams) total.merge(e.truth_.scorer);
  return total.metrics();
}

}  // namespace holo::depthfilter
