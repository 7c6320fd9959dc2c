#include "holo/eval/calibration_evaluation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "holo/calib/auto_calibration.hpp"
#include "holo/calib/calibration_io.hpp"
#include "holo/calib/capture_rig.hpp"
#include "holo/calib/pose.hpp"
#include "holo/capture/recording.hpp"
#include "holo/capture/recording_source.hpp"
#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/pipeline/installation.hpp"

namespace holo::eval {
namespace {

namespace fs = std::filesystem;

std::map<std::string, std::string> readKeyValues(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "", "the recording's scene.txt (holopyramid simulate)", "missing");
  std::map<std::string, std::string> values;
  std::string line;
  while (std::getline(in, line)) {
    const auto colon = line.find(": ");
    if (colon != std::string::npos) values[line.substr(0, colon)] = line.substr(colon + 2);
  }
  return values;
}

double relativePct(double got, double want) {
  return 100.0 * std::abs(got / want - 1.0);
}

CameraCalibrationFigures compare(const calib::CameraCalibration& got, const calib::CameraCalibration& want) {
  CameraCalibrationFigures f;
  f.serial = got.serial;
  const Intrinsics &a = got.intrinsics, &b = want.intrinsics;
  f.intrinsics_error_pct = std::max(
      {relativePct(a.fx, b.fx), relativePct(a.fy, b.fy), relativePct(a.cx, b.cx), relativePct(a.cy, b.cy)});
  const cv::Matx44d pa = calib::toMatx(got.T_world_camera), pb = calib::toMatx(want.T_world_camera);
  f.position_error_mm = 1000.0 * calib::translationError(pa, pb);
  f.rotation_error_deg = calib::rotationErrorDeg(pa, pb);
  f.depth_scale_error_pct = relativePct(got.depth_scale, want.depth_scale);
  for (int c = 0; c < 3; ++c)
    f.gain_error_pct = std::max(f.gain_error_pct, relativePct(got.colour_gains[c], want.colour_gains[c]));
  return f;
}

// The recording as an installation whose calibration is `calibration_dir`: absolute paths, so
// the file can live anywhere (it is written beside the results to rerun with `run --config`).
std::string runYaml(const fs::path& recording, const fs::path& calibration_dir, const ConfigNode& original,
                    int cameras) {
  std::string yaml = "capture:\n  calibration_dir: " + calibration_dir.string() + "\n  cameras:\n";
  for (int c = 0; c < cameras; ++c)
    yaml += fmt::format("    - {{face: {0}, backend: recording, path: \"{1}\", camera: {0}}}\n", c,
                        recording.string());
  const ConfigNode exhibit = original["exhibit"];
  yaml += "exhibit:\n  relic: " + exhibit["relic"].as<std::string>() + "\n  panorama: \"" +
          (recording / "panorama.exr").string() +
          "\"\n  fps: " + fmt::format("{}", exhibit.get<double>("fps", 30.0)) + "\n";
  return yaml;
}

struct RunImages {
  std::vector<std::vector<cv::Mat>> views;     // per frame, per face view: display (8-bit sRGB)
  std::vector<std::vector<cv::Mat>> coverage;  // per frame, per view: relic coverage
};

// The loop on the recording's visitor frames (the calibration session's frames skipped).
RunImages runLoop(const std::string& yaml, const fs::path& yaml_file, const capture::Recording& recording,
                  int calibration_frames, int frames, int view_size, bool strip_registration) {
  writeFileAtomically(yaml_file, yaml);
  const ConfigNode root = ConfigNode::parse(yaml, yaml_file.string());
  pipeline::Installation installation = pipeline::loadInstallation(root);
  for (std::size_t c = 0; c < installation.sources.size(); ++c) {
    capture::RecordedCamera camera = recording.cameras.at(c);
    if (static_cast<int>(camera.frames.size()) < calibration_frames + frames)
      throw InputError(
          recording.root.string(), "frames",
          fmt::format("{} calibration and {} visitor frames per camera", calibration_frames, frames),
          fmt::format("{} frames of camera {}", camera.frames.size(), c));
    camera.frames = std::vector<capture::RecordedFrame>(camera.frames.begin() + calibration_frames,
                                                        camera.frames.begin() + calibration_frames + frames);
    installation.sources[c] = std::make_unique<capture::RecordingSource>(std::move(camera));
  }
  if (strip_registration) {
    std::fill(installation.colour_gains.begin(), installation.colour_gains.end(), vec3(1.0f));
    std::fill(installation.depth_correction.begin(), installation.depth_correction.end(), 1.0f);
    for (auto& reprojection : installation.depth_to_colour) reprojection.reset();
  }
  pipeline::FrameLoopOptions options;
  options.view_size = view_size;
  pipeline::FrameLoop loop(options, std::move(installation), nullptr);
  RunImages images;
  for (int f = 0; f < frames; ++f) {
    const pipeline::FrameReport report = loop.step();
    if (report.cameras_ended) break;
    std::vector<cv::Mat> views, coverage;
    for (const auto& view : loop.lastResult().views) {
      views.push_back(view.display.clone());
      coverage.push_back(view.coverage.clone());
    }
    images.views.push_back(std::move(views));
    images.coverage.push_back(std::move(coverage));
  }
  loop.finish();
  return images;
}

DisplayedError displayedError(std::string run, const RunImages& got, const RunImages& want) {
  DisplayedError e;
  e.run = std::move(run);
  double sum = 0, relic_sum = 0;
  std::int64_t count = 0, relic_count = 0;
  const std::size_t frames = std::min(got.views.size(), want.views.size());
  for (std::size_t f = 0; f < frames; ++f) {
    double frame_sum = 0;
    std::int64_t frame_count = 0;
    for (std::size_t v = 0; v < want.views[f].size() && v < got.views[f].size(); ++v) {
      cv::Mat diff;
      cv::absdiff(got.views[f][v], want.views[f][v], diff);
      const cv::Scalar total = cv::sum(diff);
      frame_sum += total[0] + total[1] + total[2];
      frame_count += 3 * static_cast<std::int64_t>(diff.total());
      const cv::Mat relic = want.coverage[f][v] > 0.0f;
      const cv::Scalar on_relic = cv::sum(diff.setTo(cv::Scalar::all(0), ~relic));
      relic_sum += on_relic[0] + on_relic[1] + on_relic[2];
      relic_count += 3 * static_cast<std::int64_t>(cv::countNonZero(relic));
    }
    sum += frame_sum;
    count += frame_count;
    if (frame_count > 0) e.max_codes = std::max(e.max_codes, frame_sum / static_cast<double>(frame_count));
  }
  e.mean_codes = count > 0 ? sum / static_cast<double>(count) : 0.0;
  e.relic_codes = relic_count > 0 ? relic_sum / static_cast<double>(relic_count) : 0.0;
  return e;
}

// One row per run (true, fitted, without) and their differences x10, the last frame's four views.
cv::Mat differenceSheet(const std::vector<const RunImages*>& runs) {
  const auto row = [](const std::vector<cv::Mat>& views) {
    cv::Mat out;
    cv::hconcat(views, out);
    return out;
  };
  const std::vector<cv::Mat>& truth = runs[0]->views.back();
  std::vector<cv::Mat> rows{row(truth)};
  for (std::size_t r = 1; r < runs.size(); ++r) rows.push_back(row(runs[r]->views.back()));
  for (std::size_t r = 1; r < runs.size(); ++r) {
    std::vector<cv::Mat> diffs;
    for (std::size_t v = 0; v < truth.size(); ++v) {
      cv::Mat diff;
      cv::absdiff(runs[r]->views.back()[v], truth[v], diff);
      diffs.push_back(diff * 10.0);
    }
    rows.push_back(row(diffs));
  }
  cv::Mat sheet;
  cv::vconcat(rows, sheet);
  return sheet;
}

}  // namespace

CalibrationEvaluation evaluateCalibration(const CalibrationEvalOptions& options, std::ostream& log) {
  const fs::path recording_dir = fs::absolute(options.recording).lexically_normal();
  const fs::path out = fs::absolute(options.out).lexically_normal();
  const fs::path config_file = recording_dir / "installation.yaml";
  const fs::path truth_dir = recording_dir / "truth" / "calibration";
  std::error_code ec;
  if (!fs::is_regular_file(config_file, ec) || !fs::is_directory(truth_dir, ec))
    throw InputError(recording_dir.string(), "--recording",
                     "a recording made by `holopyramid simulate --calibration` (installation.yaml, "
                     "truth/calibration/)",
                     "no such files");
  const auto scene = readKeyValues(recording_dir / "scene.txt");
  if (!scene.count("calibration_frames"))
    throw InputError((recording_dir / "scene.txt").string(), "calibration_frames",
                     "the number of calibration frames", "missing");
  const int calibration_frames = std::stoi(scene.at("calibration_frames"));
  if (options.frames < 1) throw InputError("", "--frames", "at least 1", std::to_string(options.frames));
  fs::create_directories(out);

  CalibrationEvaluation result;
  result.view_size = options.view_size;
  const fs::path fitted_dir = out / "calibration";
  std::vector<std::string> serials;
  {
    calib::ConfiguredRig configured = calib::loadConfiguredRig(config_file);
    calib::AutoCalibrationConfig config;
    config.intrinsics_board = calib::BoardSpec::parse(calib::kDefaultIntrinsicsBoard);
    config.placement_board = calib::BoardSpec::parse(calib::kDefaultPlacementBoard);
    config.placements = calib::defaultBoardPlacements(config.placement_board, configured.rig->cameraCount());
    config.background_frames = options.background_frames;
    log << "calibrating " << configured.rig->describe() << " into " << fitted_dir.string() << "\n";
    const calib::AutoCalibrationReport report =
        calib::runAutoCalibration(*configured.rig, config, fitted_dir, log, options.quiet);
    result.calibration_passed = report.saved;
    for (int c = 0; c < configured.rig->cameraCount(); ++c) serials.push_back(configured.rig->serial(c));
  }
  if (!result.calibration_passed) {
    writeFileAtomically(out / "calibration_eval.json", calibrationEvaluationJson(result));
    return result;
  }

  result.worst.serial = "all";
  for (const std::string& serial : serials) {
    const CameraCalibrationFigures f =
        compare(calib::loadCameraCalibration(calib::cameraCalibrationPath(fitted_dir, serial)),
                calib::loadCameraCalibration(calib::cameraCalibrationPath(truth_dir, serial)));
    result.worst.intrinsics_error_pct = std::max(result.worst.intrinsics_error_pct, f.intrinsics_error_pct);
    result.worst.position_error_mm = std::max(result.worst.position_error_mm, f.position_error_mm);
    result.worst.rotation_error_deg = std::max(result.worst.rotation_error_deg, f.rotation_error_deg);
    result.worst.depth_scale_error_pct =
        std::max(result.worst.depth_scale_error_pct, f.depth_scale_error_pct);
    result.worst.gain_error_pct = std::max(result.worst.gain_error_pct, f.gain_error_pct);
    result.cameras.push_back(f);
    log << fmt::format(
        "  {}: intrinsics {:.3f} %, position {:.2f} mm, rotation {:.3f} deg, depth scale {:.3f} %, "
        "colour gains {:.2f} %\n",
        serial, f.intrinsics_error_pct, f.position_error_mm, f.rotation_error_deg, f.depth_scale_error_pct,
        f.gain_error_pct);
  }

  // The true calibration with the background the fitted one captured: the runs differ only in
  // what a calibration fits.
  const fs::path true_dir = out / "true_calibration";
  fs::remove_all(true_dir, ec);
  fs::create_directories(true_dir);
  for (const auto& entry : fs::directory_iterator(truth_dir))
    fs::copy_file(entry.path(), true_dir / entry.path().filename());
  for (const auto& entry : fs::directory_iterator(fitted_dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("background_", 0) == 0 && entry.path().extension() == ".png")
      fs::copy_file(entry.path(), true_dir / name, fs::copy_options::overwrite_existing);
  }

  const ConfigNode original = ConfigNode::loadFile(config_file);
  const capture::Recording recording = capture::readRecording(recording_dir);
  const int cameras = static_cast<int>(serials.size());
  log << "running the loop on " << options.frames << " visitor frames: true calibration\n";
  const RunImages truth = runLoop(runYaml(recording_dir, true_dir, original, cameras), out / "run_true.yaml",
                                  recording, calibration_frames, options.frames, options.view_size, false);
  log << "  fitted calibration\n";
  const RunImages fitted =
      runLoop(runYaml(recording_dir, fitted_dir, original, cameras), out / "run_fitted.yaml", recording,
              calibration_frames, options.frames, options.view_size, false);
  log << "  fitted calibration without depth registration and colour matching\n";
  const RunImages without =
      runLoop(runYaml(recording_dir, fitted_dir, original, cameras), out / "run_fitted.yaml", recording,
              calibration_frames, options.frames, options.view_size, true);
  result.frames = static_cast<int>(truth.views.size());
  if (result.frames == 0) throw Error("evaluateCalibration: the loop rendered no frame");
  result.displayed.push_back(displayedError("fitted", fitted, truth));
  result.displayed.push_back(displayedError("without registration and colour matching", without, truth));
  for (const DisplayedError& e : result.displayed)
    log << fmt::format(
        "  displayed error against the true calibration, {}: mean {:.3f} sRGB codes "
        "(on the relic {:.3f}, worst frame {:.3f})\n",
        e.run, e.mean_codes, e.relic_codes, e.max_codes);

  const fs::path png = out / "calibration_eval.png";
  const cv::Mat sheet = differenceSheet({&truth, &fitted, &without});
  writeAtomically(png, [&](const fs::path& tmp) {
    if (!cv::imwrite(tmp.string(), sheet)) throw Error("could not write " + png.string());
  });
  writeFileAtomically(out / "calibration_eval.json", calibrationEvaluationJson(result));
  return result;
}

std::string calibrationEvaluationJson(const CalibrationEvaluation& e) {
  const auto figures = [](const CameraCalibrationFigures& f) {
    return nlohmann::json{{"serial", f.serial},
                          {"intrinsics_error_pct", f.intrinsics_error_pct},
                          {"position_error_mm", f.position_error_mm},
                          {"rotation_error_deg", f.rotation_error_deg},
                          {"depth_scale_error_pct", f.depth_scale_error_pct},
                          {"gain_error_pct", f.gain_error_pct}};
  };
  nlohmann::json j;
  j["calibration_passed"] = e.calibration_passed;
  j["worst"] = figures(e.worst);
  j["cameras"] = nlohmann::json::array();
  for (const auto& c : e.cameras) j["cameras"].push_back(figures(c));
  j["frames"] = e.frames;
  j["view_size"] = e.view_size;
  j["displayed"] = nlohmann::json::array();
  for (const auto& d : e.displayed)
    j["displayed"].push_back({{"run", d.run},
                              {"mean_codes", d.mean_codes},
                              {"relic_codes", d.relic_codes},
                              {"max_codes", d.max_codes}});
  return j.dump(2) + "\n";
}

}  // namespace holo::eval
