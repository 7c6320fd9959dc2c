// `holopyramid eval depth`: runs the simulated museum through the pull-push temporal depth filter
// and its baselines (raw, temporal median, TAA) and reports the paper's Table 2 metrics as JSON
// (docs/depthfilter.md); --images writes a Fig. 9-like picture of each method's point cloud.
// `--recording DIR` instead runs a recording without truth (ours from `holopyramid simulate`, a
// TUM sequence folder) through the product's foreground pipeline and reports what can be measured
// without it (holo/eval/depth_stability.hpp); --images writes depth_stability.png.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "command.hpp"
#include "holo/capture/recording.hpp"
#include "holo/capture/recording_source.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/progress.hpp"
#include "holo/depthfilter/cloud_view.hpp"
#include "holo/depthfilter/depth_evaluation.hpp"
#include "holo/depthfilter/foreground_pipeline.hpp"
#include "holo/eval/depth_stability.hpp"
#include "holo/sim/museum.hpp"

namespace holo::app {
namespace {

namespace fs = std::filesystem;
using namespace holo::depthfilter;

struct Options {
  std::string scene = "museum";
  std::string visitor_model;  // empty: the scene's own
  int frames = 60;
  int width = 0;
  int height = 0;
  int learning_frames = TemporalDepthFilterConfig{}.learning_frames;
  std::string json;
  std::string images;
  std::string recording;
  int background_frames = 8;
};

// NaN (nothing to score) is written as null.
nlohmann::json toJson(const DepthMethodMetrics& m) {
  return {{"temporal_mse_cm2", m.temporal_mse_cm2},
          {"depth_rmse_cm", m.depth_rmse_cm},
          {"coverage", m.coverage},
          {"hole_pair_ratio", m.hole_pair_ratio},
          {"raw_holes_filled", m.raw_holes_filled},
          {"ghost_ratio", m.ghost_ratio},
          {"depth_change_cm2", m.depth_change_cm2},
          {"sensor_rmse_cm", m.sensor_rmse_cm},
          {"sensor_temporal_mse_cm2", m.sensor_temporal_mse_cm2},
          {"ms_per_frame", m.ms_per_frame},
          {"scored_frames", m.scored_frames}};
}

nlohmann::json toJson(const DepthBarVerdicts& v) {
  return {{"below_median", v.below_median}, {"below_taa", v.below_taa}, {"rmse_below_raw", v.rmse_below_raw},
          {"coverage", v.coverage},         {"ghosts", v.ghosts},       {"all", v.all()}};
}

cv::Mat labelled(cv::Mat picture, const std::string& label) {
  cv::putText(picture, label, {8, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(255, 255, 255), 2);
  return picture;
}

// Colour frame, then each method's cloud and the truth, seen 0.8 m behind and 0.2 m to the right
// of the camera (the paper's Fig. 9 viewpoint).
void writeFigure(const fs::path& dir, const sim::Museum& museum, int camera, const sim::SimulatedFrame& frame,
                 const DepthFilterEvaluation& evaluation) {
  const Intrinsics& K = museum.camera(camera).intrinsics();
  const vec3 shift(0.2f, 0.0f, -0.8f);
  double far = 0.0;
  cv::minMaxLoc(frame.true_depth, nullptr, &far, nullptr, nullptr, evaluation.lastMask());
  const float far_m = std::max(1.0f, float(far));
  std::vector<cv::Mat> panels{labelled(frame.frame.colour.clone(), "camera " + std::to_string(camera))};
  for (DepthMethod m : {DepthMethod::Raw, DepthMethod::Median, DepthMethod::Taa, DepthMethod::Ours})
    panels.push_back(
        labelled(renderShiftedCloud(evaluation.lastOutput(m), K, shift, 0.3f, far_m), depthMethodName(m)));
  cv::Mat truth = cv::Mat::zeros(frame.true_depth.size(), CV_32FC1);
  frame.true_depth.copyTo(truth, frame.foreground);
  panels.push_back(labelled(renderShiftedCloud(truth, K, shift, 0.3f, far_m), "truth"));
  cv::Mat row;
  cv::hconcat(panels, row);
  fs::create_directories(dir);
  const fs::path path = dir / "depth_methods.png";
  std::vector<std::uint8_t> png;
  cv::imencode(".png", row, png);
  writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  std::cerr << "wrote " << path.string() << "\n";
}

nlohmann::json nullable(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json toJson(const eval::EdgeAndFlicker& f) {
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
void writeStabilityFigure(const fs::path& dir, const RgbdFrame& frame, const cv::Mat& filtered,
                          const eval::DepthStabilityMeter& meter, int pairs) {
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
  fs::create_directories(dir);
  const fs::path path = dir / "depth_stability.png";
  std::vector<std::uint8_t> png;
  cv::imencode(".png", figure, png);
  writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  std::cerr << "wrote " << path.string() << "\n";
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

int runRecording(const Options& o) {
  if (o.background_frames < 0)
    throw InputError("", "--background-frames", "a number of frames >= 0",
                     std::to_string(o.background_frames));
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

  std::vector<eval::DepthStabilityMeter> meters(sources.size());
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

  const eval::DepthStabilityFigures f = eval::DepthStabilityMeter::combined(meters);
  nlohmann::json noise_at;
  for (std::size_t k = 0; k < eval::kBackgroundNoiseDepths.size(); ++k)
    noise_at[std::to_string(int(eval::kBackgroundNoiseDepths[k])) + "m"] =
        nullable(f.background_noise_mm_at[k]);
  const nlohmann::json report = {
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
  std::cout << report.dump(2) << "\n";
  if (!o.json.empty()) writeFileAtomically(o.json, report.dump(2) + "\n");
  if (!o.images.empty()) {
    std::size_t shown = 0;
    for (std::size_t c = 0; c < sources.size(); ++c)
      if (cv::countNonZero(pipeline.lastResult(c).mask) > cv::countNonZero(pipeline.lastResult(shown).mask))
        shown = c;
    writeStabilityFigure(o.images, current[shown], pipeline.lastResult(shown).depth, meters[shown],
                         meters[shown].figures().frame_pairs);
  }
  return 0;
}

int run(const Options& o) {
  if (o.learning_frames < 0)
    throw InputError("", "--learning-frames", "a number of frames >= 0", std::to_string(o.learning_frames));
  if (!o.recording.empty()) return runRecording(o);
  if (o.frames < 1) throw InputError("", "--frames", "a number of frames >= 1", std::to_string(o.frames));
  sim::SceneDescription description = sim::loadScene(o.scene);
  if (o.width > 0) description.camera.width = o.width;
  if (o.height > 0) description.camera.height = o.height;
  if (!o.visitor_model.empty())
    description.visitor_model = sim::visitorModelFromName(o.visitor_model, "", "--visitor-model");
  const sim::Museum museum(description);

  DepthEvaluationConfig config;
  config.filter.learning_frames = o.learning_frames;
  std::vector<DepthFilterEvaluation> streams;
  for (int c = 0; c < museum.cameraCount(); ++c) streams.emplace_back(config);
  constexpr int kBackgroundFrames = 8;
  const int total = o.learning_frames + o.frames;
  ProgressReporter progress(std::int64_t(museum.cameraCount()) * (kBackgroundFrames + total), "eval depth");
  for (int c = 0; c < museum.cameraCount(); ++c)
    for (int t = 0; t < kBackgroundFrames; ++t, progress.update())
      streams[std::size_t(c)].learnBackground(museum.renderCamera(c, t, false).frame);

  int figure_camera = 0;
  long figure_pixels = -1;
  sim::SimulatedFrame figure_frame;
  for (int t = 0; t < total; ++t)
    for (int c = 0; c < museum.cameraCount(); ++c, progress.update()) {
      sim::SimulatedFrame f = museum.renderCamera(c, t);
      streams[std::size_t(c)].addFrame({f.frame, f.true_depth, f.foreground});
      if (t + 1 == total && cv::countNonZero(f.foreground) > figure_pixels) {
        figure_pixels = cv::countNonZero(f.foreground);
        figure_camera = c;
        figure_frame = std::move(f);
      }
    }
  progress.done();

  nlohmann::json methods, bars;
  std::vector<std::pair<std::string, DepthMethodMetrics>> rows;
  for (DepthMethod m : kDepthMethods) {
    rows.emplace_back(depthMethodName(m), DepthFilterEvaluation::combined(streams, m));
    methods[depthMethodName(m)] = toJson(rows.back().second);
  }
  const auto combined = [&](DepthMethod m) { return rows[std::size_t(m)].second; };
  for (DepthMethod m : {DepthMethod::Ours, DepthMethod::Adversary})
    bars[depthMethodName(m)] = toJson(checkDepthBars(
        combined(m), combined(DepthMethod::Raw), combined(DepthMethod::Median), combined(DepthMethod::Taa)));
  const nlohmann::json report = {
      {"scene", description.name},
      {"frames", o.frames},
      {"learning_frames", o.learning_frames},
      {"cameras", museum.cameraCount()},
      {"width", description.camera.width},
      {"height", description.camera.height},
      {"methods", methods},
      {"bars", bars},
      {"truth_depth_change_cm2", DepthFilterEvaluation::combinedTruth(streams).depth_change_cm2}};
  std::cout << report.dump(2) << "\n";
  std::cerr << depthMetricsTable(rows);
  if (!o.json.empty()) writeFileAtomically(o.json, report.dump(2) + "\n");
  if (!o.images.empty())
    writeFigure(o.images, museum, figure_camera, figure_frame, streams[std::size_t(figure_camera)]);
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "eval depth",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      sub.add_option("--scene", o->scene, "Built-in scene name or scene YAML file")->capture_default_str();
      sub.add_option("--frames", o->frames, "Scored frames after the learning frames")->capture_default_str();
      sub.add_option("--learning-frames", o->learning_frames, "Frames C that only learn the PDFs")
          ->capture_default_str();
      sub.add_option("--width", o->width, "Camera width (default: the scene's)");
      sub.add_option("--height", o->height, "Camera height (default: the scene's)");
      sub.add_option("--visitor-model", o->visitor_model,
                     "Visitors instead of the scene's: bodies (the default) or figures");
      sub.add_option("--json", o->json, "Write the report to this JSON file");
      sub.add_option(
          "--images", o->images,
          "Write depth_methods.png (Fig. 9-like; with --recording depth_stability.png) into this folder");
      sub.add_option("--recording", o->recording,
                     "Measure a recording without truth instead (holopyramid simulate's folder or a TUM "
                     "sequence): hole flicker, background noise, edge jitter");
      sub.add_option("--background-frames", o->background_frames,
                     "With --recording and no background/ folder: the first N frames are the empty room")
          ->capture_default_str();
      return [o] { return run(*o); };
    },
    "Temporal depth filter vs raw, median and TAA on a simulated scene (paper Table 2), or a recording "
    "without truth"});

}  // namespace holo::app
