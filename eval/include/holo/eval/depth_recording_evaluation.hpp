// The depth filter on a recording without truth (`holopyramid eval depth --recording`; ours from
// `holopyramid simulate`, or a TUM sequence folder): every camera through the product's foreground
// pipeline, after the recording's background frames (or, without a background/ folder, its first
// frames standing in for the empty room) and the filter's learning frames, and what can be
// measured without the truth (depth_stability.hpp), pooled over the cameras, as a JSON report
// (NaN written as null).
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

namespace holo::eval {

struct DepthRecordingOptions {
  std::string recording;      // the recording's folder
  int learning_frames = 0;    // frames that only learn the filter's PDFs (>= 0)
  int background_frames = 8;  // without a background/ folder: the first frames taken as the empty room (>= 0)
  bool figure = false;        // also draw DepthRecordingEvaluation::figure
};

struct DepthRecordingEvaluation {
  // recording, layout, cameras, background, learning_frames, frame_pairs, foreground (raw and
  // filtered hole flicker and edge jitter), background_raw, background_noise_mm (overall and at
  // kBackgroundNoiseDepths), background_noise_pixels.
  nlohmann::json report;
  // With DepthRecordingOptions::figure, for the camera whose last frame has the most foreground
  // pixels (BGR): colour, raw depth and filtered depth of the last frame over where the raw and
  // the filtered depth flickered and the background's temporal noise.
  cv::Mat figure;
};

// Throws InputError when the recording is shorter than its background, learning frames and two
// frames to compare.
DepthRecordingEvaluation evaluateDepthRecording(const DepthRecordingOptions& options);

}  // namespace holo::eval
