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
    if (score) {
      Sums& s = state.sums;
      s.seconds += seconds;
      ++s.frames;
      double change_sum = 0.0;
      long change_n = 0;
      for (int y = 0; y < out.rows; ++y) {
        const float* d = out.ptr<float>(y);
        const float* td = truth.true_depth.ptr<float>(y);
        const std::uint8_t* tf = truth.true_foreground.ptr<std::uint8_t>(y);
        const std::uint8_t* m = last_mask_.ptr<std::uint8_t>(y);
        const float* prev = state.last_scored ? state.last_output.ptr<float>(y) : nullptr;
        for (int x = 0; x < out.cols; ++x) {
          const bool has = d[x] > 0.0f;
          if (tf[x] && m[x]) {
            ++s.fill_n;
            s.fill_hits += has;
          }
          if (!has) continue;
          ++s.outputs;
          if (!tf[x]) {
            ++s.ghosts;
          } else if (td[x] > 0.0f) {
            const double e = 100.0 * (double(d[x]) - td[x]);
            s.error_sq_sum += e * e;
            ++s.error_n;
          }
          if (prev && prev[x] > 0.0f) {
            const double c = 100.0 * (double(d[x]) - prev[x]);
            change_sum += c * c;
            ++change_n;
          }
        }
      }
      if (change_n > 0) {
        s.temporal_sum += change_sum / double(change_n);
        ++s.temporal_pairs;
      }
    }
    state.last_output = out;
    state.last_scored = score;
  }
}

DepthMethodMetrics DepthFilterEvaluation::toMetrics(const Sums& s) {
  DepthMethodMetrics m;
  m.temporal_mse_cm2 = s.temporal_pairs > 0 ? s.temporal_sum / double(s.temporal_pairs) : 0.0;
  m.depth_rmse_cm = s.error_n > 0 ? std::sqrt(s.error_sq_sum / double(s.error_n)) : 0.0;
  m.hole_fill_ratio = s.fill_n > 0 ? double(s.fill_hits) / double(s.fill_n) : 1.0;
  m.ghost_ratio = s.outputs > 0 ? double(s.ghosts) / double(s.outputs) : 0.0;
  m.ms_per_frame = s.frames > 0 ? 1000.0 * s.seconds / double(s.frames) : 0.0;
  m.scored_frames = s.frames;
  return m;
}

DepthMethodMetrics DepthFilterEvaluation::metrics(DepthMethod method) const {
  return toMetrics(methods_[std::size_t(method)].sums);
}

DepthMethodMetrics DepthFilterEvaluation::combined(std::span<const DepthFilterEvaluation> streams,
                                                   DepthMethod method) {
  Sums total;
  for (const DepthFilterEvaluation& e : streams) {
    const Sums& s = e.methods_[std::size_t(method)].sums;
    total.temporal_sum += s.temporal_sum;
    total.temporal_pairs += s.temporal_pairs;
    total.error_sq_sum += s.error_sq_sum;
    total.error_n += s.error_n;
    total.fill_hits += s.fill_hits;
    total.fill_n += s.fill_n;
    total.ghosts += s.ghosts;
    total.outputs += s.outputs;
    total.seconds += s.seconds;
    total.frames += s.frames;
  }
  // Frames are counted per stream; time per frame is per camera frame.
  return toMetrics(total);
}

}  // namespace holo::depthfilter
