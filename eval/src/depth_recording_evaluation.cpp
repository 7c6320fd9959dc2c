#include "holo/eval/depth_recording_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "figure_label.hpp"
#include "holo/capture/recording.hpp"
#include "holo/capture/recording_source.hpp"
#include "holo/core/error.hpp"
#include "holo/core/progress.hpp"
#include "holo/depthfilter/foreground_pipeline.hpp"
#include "holo/eval/depth_stability.hpp"

namespace holo::eval {
namespace {

namespace fs = std::filesystem;

nlohmann::json nullable(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json toJson(const EdgeAndFlicker& f) {
  return {{"hole_flicker", nullable(f.hole_flicker)},
          {"pixel_pairs", f.pixel_pairs},
          {"edge_jitter_px", nullable(f.edge_jitter_px)},
          {"edge_pixels", f.edge_pixels}};
}

cv::Mat colourDepth(const cv::Mat& depth, float far_m) {
  cv::Mat scaled, out;
  depth.convertTo(scaled, CV_8U, -255.0 / far_m, 255.0);
  cv::applyColorMap(scaled, out, cv::COLORMAP_TURBO);
  out.setTo(cv::Scalar::all(0), depth <= 0.0f);
  return out;
}

cv::Mat heat(const cv::Mat& values, double top) {
  cv::Mat scaled, out;
  values.convertTo(scaled, CV_8U, 255.0 / std::max(top, 1e-9));
  cv::applyColorMap(scaled, out, cv::COLORMAP_INFERNO);
  return out;
}

// Colour, raw depth, filtered depth (last frame), where raw and filtered depth flickered and the
// background's temporal noise, for one camera.
cv::Mat stabilityFigure(const RgbdFrame& frame, const cv::Mat& filtered, const DepthStabilityMeter& meter,
                        int pairs) {
  double far = 0;
  cv::minMaxLoc(frame.depth, nullptr, &far);
  const float far_m = std::max(1.0f, float(far));
  const std::vector<cv::Mat> panels{
      labelled(frame.colour.clone(), "colour"),
      labelled(colourDepth(frame.depth, far_m), "raw depth"),
      labelled(colourDepth(filtered, far_m), "filtered (foreground)"),
      labelled(heat(meter.rawFlickerCount(), std::max(1, pairs / 2)), "raw hole flicker"),
      labelled(heat(meter.filteredFlickerCount(), std::max(1, pairs / 2)), "filtered hole flicker"),
      labelled(heat(meter.backgroundNoiseMm(), 20.0), "background std 0-20 mm")};
  cv::Mat top, bottom, figure;
  cv::hconcat(std::vector<cv::Mat>(panels.begin(), panels.begin() + 3), top);
  cv::hconcat(std::vector<cv::Mat>(panels.begin() + 3, panels.end()), bottom);
  cv::vconcat(top, bottom, figure);
  return figure;
}

// A camera model for a recording that has none: TUM's default Kinect intrinsics scaled to the
// frame size (only the foreground cloud, which this evaluation does not score, uses it).
CameraModel modelFor(const capture::RecordedCamera& camera, const cv::Size& size) {
  if (camera.model) return *camera.model;
  Intrinsics K;
  K.width = size.width;
  K.height = size.height;
  K.fx = K.fy = 525.0f * float(size.width) / 640.0f;
  K.cx = 0.5f * float(size.width) - 0.5f;
  K.cy = 0.5f * float(size.height) - 0.5f;
  return CameraModel(K, mat4(1.0f));
}

RgbdFrame loadImage(const fs::path& colour, const fs::path& depth, double depth_scale) {
  RgbdFrame frame;
  frame.colour = cv::imread(colour.string(), cv::IMREAD_COLOR);
  const cv::Mat raw = cv::imread(depth.string(), cv::IMREAD_ANYDEPTH);
  if (frame.colour.empty()) throw InputError(colour.string(), "", "a readable colour image", "cannot decode");
  if (raw.type() != CV_16UC1) throw InputError(depth.string(), "", "a 16-bit depth PNG", "cannot decode");
  frame.depth = capture::depthFromU16(raw, depth_scale);
  return frame;
}

}  // namespace

DepthRecordingEvaluation evaluateDepthRecording(const DepthRecordingOptions& o) {
  const capture::Recording recording = capture::readRecording(o.recording);
  std::vector<std::unique_ptr<capture::RecordingSource>> sources;
  std::size_t frames = std::numeric_limits<std::size_t>::max();
  for (const auto& camera : recording.cameras) {
    sources.push_back(std::make_unique<capture::RecordingSource>(camera));
    frames = std::min(frames, camera.frames.size());
  }
  // The recorder's background frames (gamma_s, `holopyramid simulate` writes them); else the
  // first frames of the sequence stand in for them.
  const fs::path background_dir = fs::path(o.recording) / "background";
  const bool recorded_background = fs::exists(background_dir / "cam0" / "depth.png");
  const std::size_t skipped = recorded_background ? 0 : std::size_t(o.background_frames);
  const int learning = o.learning_frames;
  if (frames < skipped + std::size_t(learning) + 2)
    throw InputError(o.recording, "frames",
                     "a sequence of at least " + std::to_string(skipped + std::size_t(learning) + 2) +
                         " frames (background " + std::to_string(skipped) + ", learning " +
                         std::to_string(learning) + ", then at least two to compare)",
                     std::to_string(frames));

  std::vector<RgbdFrame> first;
  std::vector<CameraModel> models;
  for (const auto& source : sources) first.push_back(source->load(0));
  for (std::size_t c = 0; c < sources.size(); ++c)
    models.push_back(modelFor(recording.cameras[c], first[c].depth.size()));
  depthfilter::ForegroundPipelineConfig config;
  config.filter.learning_frames = learning;
  depthfilter::ForegroundPipeline pipeline(models, config);
  if (recorded_background) {
    std::vector<RgbdFrame> background;
    for (std::size_t c = 0; c < sources.size(); ++c) {
      const fs::path dir = background_dir / ("cam" + std::to_string(c));
      background.push_back(loadImage(dir / "color.png", dir / "depth.png", recording.cameras[c].depth_scale));
    }
    pipeline.learnBackground(background);
  } else {
    for (std::size_t t = 0; t < skipped; ++t) {
      std::vector<RgbdFrame> background;
      for (const auto& source : sources) background.push_back(source->load(t));
      pipeline.learnBackground(background);
    }
  }

  std::vector<DepthStabilityMeter> meters(sources.size());
  std::vector<RgbdFrame> current;
  ProgressReporter progress(std::int64_t(frames - skipped), "eval depth");
  for (std::size_t t = skipped; t < frames; ++t, progress.update()) {
    current.clear();
    for (const auto& source : sources) current.push_back(source->load(t));
    pipeline.process(current);
    if (pipeline.filter(0).learning()) continue;
    for (std::size_t c = 0; c < sources.size(); ++c) {
      const depthfilter::CameraForeground& r = pipeline.lastResult(c);
      meters[c].addFrame(current[c].depth, r.mask, r.depth);
    }
  }
  progress.done();

  const DepthStabilityFigures f = DepthStabilityMeter::combined(meters);
  nlohmann::json noise_at;
  for (std::size_t k = 0; k < kBackgroundNoiseDepths.size(); ++k)
    noise_at[std::to_string(int(kBackgroundNoiseDepths[k])) + "m"] = nullable(f.background_noise_mm_at[k]);
  DepthRecordingEvaluation result;
  result.report = {
      {"recording", o.recording},
      {"layout", recording.layout},
      {"cameras", sources.size()},
      {"background", recorded_background ? "recorded" : "first " + std::to_string(skipped) + " frames"},
      {"learning_frames", learning},
      {"frame_pairs", f.frame_pairs},
      {"foreground", {{"raw", toJson(f.raw)}, {"filtered", toJson(f.filtered)}}},
      {"background_raw", toJson(f.background)},
      {"background_noise_mm", nullable(f.background_noise_mm)},
      {"background_noise_mm_at", noise_at},
      {"background_noise_pixels", f.background_noise_pixels}};
  if (o.figure) {
    std::size_t shown = 0;
    for (std::size_t c = 0; c < sources.size(); ++c)
      if (cv::countNonZero(pipeline.lastResult(c).mask) > cv::countNonZero(pipeline.lastResult(shown).mask))
        shown = c;
    result.figure = stabilityFigure(current[shown], pipeline.lastResult(shown).depth, meters[shown],
                                    meters[shown].figures().frame_pairs);
  }
  return result;
}

}  // namespace holo::eval
