#include "holo/calib/calibration_session.hpp"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/calib/background.hpp"
#include "holo/calib/display_alignment.hpp"
#include "holo/calib/extrinsics.hpp"
#include "holo/calib/intrinsics.hpp"
#include "holo/calib/panorama_alignment.hpp"
#include "holo/calib/pose.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/median.hpp"
#include "holo/core/progress.hpp"

namespace holo::calib {

namespace fs = std::filesystem;

namespace {

void addVerdict(StepOutcome& out, std::ostream& log, StepVerdict verdict) {
  log << formatVerdict(verdict) << "\n";
  out.verdicts.push_back(std::move(verdict));
}

void preview(StepOutcome& out, const CalibrationSession::PreviewCallback& on_preview, std::string label,
             cv::Mat picture) {
  if (on_preview) on_preview(static_cast<int>(out.previews.size()), label, picture);
  out.previews.emplace_back(std::move(label), std::move(picture));
}

// The linear HDR panorama as an 8-bit picture (Reinhard, then sRGB-like gamma) for the preview.
cv::Mat panoramaPicture(const cv::Mat& panorama) {
  cv::Mat mapped = panorama / (panorama + cv::Scalar::all(1.0));
  cv::pow(mapped, 1.0 / 2.2, mapped);
  cv::Mat out;
  mapped.convertTo(out, CV_8UC3, 255.0);
  return out;
}

std::string cameraLabel(const CalibrationRig& rig, int c) {
  return "camera " + std::to_string(c) + " (" + rig.serial(c) + ")";
}

}  // namespace

const char* stepTitle(CalibrationStep step) {
  switch (step) {
    case CalibrationStep::Intrinsics:
      return "intrinsics";
    case CalibrationStep::Poses:
      return "camera poses";
    case CalibrationStep::Background:
      return "background";
    case CalibrationStep::Panorama:
      return "panorama yaw";
    case CalibrationStep::Display:
      return "display alignment";
    case CalibrationStep::Save:
      return "save";
  }
  return "?";
}

const char* stepInstructions(CalibrationStep step) {
  switch (step) {
    case CalibrationStep::Intrinsics:
      return "Hold the small ChArUco board 30-45 cm in front of each camera. Tilt it and move it into "
             "every part of the picture, holding it still for each photo. Every camera needs at least 8 "
             "photos in which the board is found.";
    case CalibrationStep::Poses:
      return "Stand the large ChArUco board on the easel at the marked spot in front of each face of the "
             "pyramid. Nothing may cover it; it must not move while the photos are taken.";
    case CalibrationStep::Background:
      return "Clear the hall: take the boards away and make sure nobody stands in front of the cameras. "
             "Each camera records several frames of the empty hall; keep the lights as they are during "
             "opening hours.";
    case CalibrationStep::Panorama:
      return "Nothing to do: the hall panorama is turned until it matches what the calibrated cameras see. "
             "If this fails, the panorama was taken in another hall or the furniture has moved.";
    case CalibrationStep::Display:
      return "Each face shows the test pattern. Its 25 dots are found on the monitor and the face's "
             "offset, scale, rotation and mirror are fitted. The arrow must point up and the number read "
             "normally on the pyramid.";
    case CalibrationStep::Save:
      return "Every step passed. Save writes the calibration into the output folder; the previous "
             "calibration is kept as .bak beside each file.";
  }
  return "";
}

bool StepOutcome::passed() const {
  return error.empty() && !verdicts.empty() &&
         std::all_of(verdicts.begin(), verdicts.end(), [](const StepVerdict& v) { return v.pass; });
}

CalibrationSession::CalibrationSession(const CalibrationRig& rig, AutoCalibrationConfig config)
    : rig_(rig), config_(std::move(config)) {
  const int cameras = rig_.cameraCount();
  if (static_cast<int>(config_.placements.size()) != cameras)
    throw InputError("calibration configuration", "placements", std::to_string(cameras) + " board placements",
                     std::to_string(config_.placements.size()));
  if (config_.background_frames < 1)
    throw InputError("calibration configuration", "background_frames", "at least 1",
                     std::to_string(config_.background_frames));
  cameras_.resize(static_cast<std::size_t>(cameras));
  for (int c = 0; c < cameras; ++c) cameras_[static_cast<std::size_t>(c)].serial = rig_.serial(c);
}

const std::optional<StepOutcome>& CalibrationSession::outcome(CalibrationStep step) const {
  return outcomes_[static_cast<std::size_t>(step)];
}

const StepOutcome& CalibrationSession::measure(CalibrationStep step, std::ostream& log, bool quiet,
                                               const PreviewCallback& on_preview) {
  const auto index = static_cast<std::size_t>(step);
  HOLO_ASSERT(step != CalibrationStep::Save);
  for (std::size_t earlier = 0; earlier < index; ++earlier) HOLO_ASSERT(outcomes_[earlier].has_value());
  for (std::size_t later = index; later < outcomes_.size(); ++later) outcomes_[later].reset();
  log << "step " << index + 1 << ": " << stepTitle(step) << "\n";
  StepOutcome out;
  try {
    switch (step) {
      case CalibrationStep::Intrinsics:
        out = measureIntrinsics(log, quiet, on_preview);
        break;
      case CalibrationStep::Poses:
        out = measurePoses(log, on_preview);
        break;
      case CalibrationStep::Background:
        out = measureBackground(log, quiet, on_preview);
        break;
      case CalibrationStep::Panorama:
        out = measurePanorama(log, on_preview);
        break;
      case CalibrationStep::Display:
        out = measureDisplay(log, on_preview);
        break;
      case CalibrationStep::Save:
        break;
    }
  } catch (const InputError& e) {
    out.error = e.what();
    out.exception = std::current_exception();
    log << "  could not measure: " << out.error << "\n";
  }
  outcomes_[index] = std::move(out);
  return *outcomes_[index];
}

StepOutcome CalibrationSession::measureIntrinsics(std::ostream& log, bool quiet,
                                                  const PreviewCallback& on_preview) {
  StepOutcome out;
  log << "  board " << config_.intrinsics_board.describe() << "\n";
  for (int c = 0; c < rig_.cameraCount(); ++c) {
    std::vector<BoardView> views;
    std::vector<cv::Mat> drawn;
    std::vector<double> fractions;
    {
      ProgressReporter progress(rig_.intrinsicsViewCount(), "camera " + std::to_string(c) + " board photos",
                                quiet);
      for (int v = 0; v < rig_.intrinsicsViewCount(); ++v) {
        const cv::Mat photo = rig_.intrinsicsPhoto(c, v);
        BoardView view{"view " + std::to_string(v), detectBoard(config_.intrinsics_board, photo)};
        if (view.detection.usable()) fractions.push_back(view.detection.widthFraction(photo.cols));
        drawn.push_back(drawDetection(config_.intrinsics_board, photo, view.detection));
        if (on_preview)
          on_preview(c, cameraLabel(rig_, c) + ", photo " + std::to_string(v + 1), drawn.back());
        views.push_back(std::move(view));
        progress.update();
      }
    }
    const cv::Mat sheet = detectionContactSheet(drawn);
    out.files.emplace_back("intrinsics_camera" + std::to_string(c) + ".png", sheet);
    out.previews.emplace_back(cameraLabel(rig_, c), sheet);
    CameraCalibration& cal = cameras_[static_cast<std::size_t>(c)];
    const IntrinsicsResult result = calibrateIntrinsics(config_.intrinsics_board, views, rig_.imageSize(c),
                                                        "camera " + std::to_string(c));
    cal.intrinsics = result.intrinsics;
    cal.rms = result.rms;
    log << "  camera " << c << " (" << cal.serial << "): fx " << result.intrinsics.fx << " fy "
        << result.intrinsics.fy << " cx " << result.intrinsics.cx << " cy " << result.intrinsics.cy << "\n";
    addVerdict(out, log,
               judgeIntrinsics("intrinsics camera " + std::to_string(c), result.rms,
                               static_cast<int>(result.used_views.size()), rig_.intrinsicsViewCount(),
                               median(fractions)));
  }
  return out;
}

StepOutcome CalibrationSession::measurePoses(std::ostream& log, const PreviewCallback& on_preview) {
  StepOutcome out;
  log << "  board " << config_.placement_board.describe() << " at known placements\n";
  ExtrinsicsProblem problem;
  std::vector<double> fractions;
  for (int c = 0; c < rig_.cameraCount(); ++c) {
    problem.cameras.push_back(cameras_[static_cast<std::size_t>(c)].intrinsics);
    problem.placements.push_back({config_.placements[static_cast<std::size_t>(c)], true});
    const cv::Mat photo = rig_.placementPhoto(c);
    BoardDetection detection = detectBoard(config_.placement_board, photo);
    fractions.push_back(detection.widthFraction(photo.cols));
    const cv::Mat drawn = drawDetection(config_.placement_board, photo, detection);
    out.files.emplace_back("placement_camera" + std::to_string(c) + ".png", drawn);
    preview(out, on_preview, cameraLabel(rig_, c), drawn);
    problem.observations.push_back({c, c, std::move(detection)});
  }
  const ExtrinsicsResult poses = calibrateExtrinsics(problem, "board placements");
  for (int c = 0; c < rig_.cameraCount(); ++c) {
    const auto i = static_cast<std::size_t>(c);
    cameras_[i].T_world_camera = toMat4(poses.T_world_camera[i]);
    const auto& p = poses.T_world_camera[i];
    log << "  camera " << c << ": position " << p(0, 3) << " " << p(1, 3) << " " << p(2, 3) << " m\n";
    addVerdict(out, log,
               judgeExtrinsics("pose camera " + std::to_string(c), poses.camera_rms[i],
                               poses.camera_corners[i], fractions[i]));
  }
  return out;
}

StepOutcome CalibrationSession::measureBackground(std::ostream& log, bool quiet,
                                                  const PreviewCallback& on_preview) {
  StepOutcome out;
  log << "  " << config_.background_frames << " frames per camera\n";
  for (int c = 0; c < rig_.cameraCount(); ++c) {
    std::vector<RgbdFrame> frames;
    {
      ProgressReporter progress(config_.background_frames, "camera " + std::to_string(c) + " background",
                                quiet);
      for (int k = 0; k < config_.background_frames; ++k) {
        frames.push_back(rig_.backgroundFrame(c, k));
        if (on_preview)
          on_preview(c, cameraLabel(rig_, c) + ", frame " + std::to_string(k + 1), frames.back().colour);
        progress.update();
      }
    }
    const BackgroundModel model = captureBackground(frames, "camera " + std::to_string(c));
    out.files.emplace_back("background_camera" + std::to_string(c) + ".png", model.colour);
    cv::Mat depth_mm;
    model.depth.convertTo(depth_mm, CV_16U, 1000.0);  // PNG depth in millimetres, 0 = invalid
    out.files.emplace_back("background_depth_camera" + std::to_string(c) + ".png", depth_mm);
    out.previews.emplace_back(cameraLabel(rig_, c), model.colour);
    log << "  camera " << c << ": " << model.invalid_samples << " invalid depth samples, colour MAD "
        << model.colour_mad << "\n";
    addVerdict(
        out, log,
        judgeBackground("background camera " + std::to_string(c), model.invalid_fraction, model.colour_mad));
  }
  return out;
}

StepOutcome CalibrationSession::measurePanorama(std::ostream& log, const PreviewCallback& on_preview) {
  StepOutcome out;
  const cv::Mat panorama = rig_.panorama();
  // Every camera votes; the best-correlated one decides (the others may see mostly the pyramid).
  YawFit best{0.0f, -2.0};
  for (int c = 0; c < rig_.cameraCount(); ++c) {
    const CameraModel model = toCameraModel(cameras_[static_cast<std::size_t>(c)]);
    const RgbdFrame frame = rig_.backgroundFrame(c, 0);
    preview(out, on_preview, cameraLabel(rig_, c), frame.colour);
    const YawFit fit = alignPanoramaYaw(panorama, model, frame.colour, "camera " + std::to_string(c));
    log << "  camera " << c << ": yaw " << fit.yaw_rad * 180.0f / kPi << " deg, correlation "
        << fit.correlation << "\n";
    if (fit.correlation > best.correlation) best = fit;
  }
  pyramid_.panorama_yaw_rad = best.yaw_rad;
  pyramid_.panorama_position = config_.panorama_position;
  // The panorama as it will be used: turned by the fitted yaw (a horizontal roll of its columns).
  const cv::Mat picture = panoramaPicture(panorama);
  const int shift =
      static_cast<int>(std::lround(best.yaw_rad / (2.0f * kPi) * static_cast<float>(picture.cols)));
  cv::Mat turned(picture.size(), picture.type());
  for (int x = 0; x < picture.cols; ++x)
    picture.col(((x + shift) % picture.cols + picture.cols) % picture.cols).copyTo(turned.col(x));
  out.files.emplace_back("panorama_aligned.png", turned);
  preview(out, on_preview, "panorama turned by the fitted yaw", turned);
  addVerdict(out, log, judgePanorama("panorama yaw", best.correlation));
  return out;
}

StepOutcome CalibrationSession::measureDisplay(std::ostream& log, const PreviewCallback& on_preview) {
  StepOutcome out;
  log << "  test pattern " << config_.face_view.width << "x" << config_.face_view.height << "\n";
  const auto dots = testPatternDots(config_.face_view);
  for (int f = 0; f < kPyramidFaces; ++f) {
    const FaceFit fit = estimateFaceAlignment(dots, rig_.observedTestPattern(f, config_.face_view),
                                              config_.face_view, "face " + std::to_string(f));
    pyramid_.faces[static_cast<std::size_t>(f)] = fit.alignment;
    cv::Mat shown;
    cv::warpAffine(drawTestPattern(config_.face_view, f), shown,
                   cv::Mat(faceTransform(fit.alignment, config_.face_view)), config_.face_view);
    out.files.emplace_back("display_face" + std::to_string(f) + ".png", shown);
    preview(out, on_preview, "face " + std::to_string(f), shown);
    log << "  face " << f << ": offset " << fit.alignment.offset_px.x << " " << fit.alignment.offset_px.y
        << " px, scale " << fit.alignment.scale << ", rotation " << fit.alignment.rotation_deg << " deg"
        << (fit.alignment.mirror ? ", mirrored" : "") << "\n";
    addVerdict(out, log, judgeDisplay("display face " + std::to_string(f), fit.residual_px));
  }
  return out;
}

std::vector<fs::path> CalibrationSession::save(const fs::path& out_dir, std::ostream& log) const {
  for (int s = 0; s < kMeasuringSteps; ++s) HOLO_ASSERT(outcomes_[static_cast<std::size_t>(s)].has_value());
  fs::create_directories(out_dir);
  std::vector<fs::path> written;
  for (const CameraCalibration& cal : cameras_) {
    written.push_back(cameraCalibrationPath(out_dir, cal.serial));
    saveCameraCalibration(written.back(), cal);
  }
  written.push_back(pyramidCalibrationPath(out_dir));
  savePyramidCalibration(written.back(), pyramid_);
  for (int s = 0; s < kMeasuringSteps; ++s)
    for (const auto& file : outcomes_[static_cast<std::size_t>(s)]->files) {
      // Not a structured binding: clang 14 (the fuzz and sanitizer builds) cannot capture one.
      const cv::Mat& image = file.second;
      written.push_back(out_dir / file.first);
      writeAtomically(written.back(), [&](const fs::path& tmp) {
        if (!cv::imwrite(tmp.string(), image)) throw Error("could not write " + tmp.string());
      });
    }
  const AutoCalibrationReport summary = report();
  log << (summary.allPassed() ? "calibration saved: every step passed\n"
                              : "calibration saved, but some steps failed: see the hints above\n");
  return written;
}

AutoCalibrationReport CalibrationSession::report() const {
  AutoCalibrationReport out;
  for (const auto& outcome : outcomes_)
    if (outcome) out.verdicts.insert(out.verdicts.end(), outcome->verdicts.begin(), outcome->verdicts.end());
  out.cameras = cameras_;
  out.pyramid = pyramid_;
  return out;
}

}  // namespace holo::calib
