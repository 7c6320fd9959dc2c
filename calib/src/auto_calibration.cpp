#include "holo/calib/auto_calibration.hpp"

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
#include "holo/core/progress.hpp"

namespace holo::calib {

namespace fs = std::filesystem;

namespace {

void savePng(const fs::path& path, const cv::Mat& image) {
  writeAtomically(path, [&](const fs::path& tmp) {
    if (!cv::imwrite(tmp.string(), image)) throw Error("could not write " + tmp.string());
  });
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2),
                   values.end());
  return values[values.size() / 2];
}

void report(AutoCalibrationReport& out, std::ostream& log, StepVerdict verdict) {
  log << formatVerdict(verdict) << "\n";
  out.verdicts.push_back(std::move(verdict));
}

}  // namespace

std::vector<cv::Matx44d> defaultBoardPlacements(const BoardSpec& board, int cameras, double base_half_width) {
  std::vector<cv::Matx44d> placements;
  const cv::Rect2d e = board.extent();
  const cv::Vec3d board_centre(e.x + e.width / 2, e.y + e.height / 2, 0);
  for (int f = 0; f < cameras; ++f) {
    const double azimuth = f * CV_PI / 2;
    const cv::Vec3d out(std::sin(azimuth), 0, std::cos(azimuth));
    // Board axes in the world: +Z away from the camera (the printed side faces it), +Y down.
    const cv::Vec3d z = out, y(0, -1, 0), x = y.cross(z);
    const cv::Matx33d upright(x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2]);
    cv::Matx33d lean, turn;
    cv::Rodrigues(cv::Vec3d(12.0 * CV_PI / 180, 0, 0), lean);
    cv::Rodrigues(cv::Vec3d(0, (f % 2 ? -20.0 : 20.0) * CV_PI / 180, 0), turn);
    const cv::Matx33d R = upright * lean * turn;
    const cv::Vec3d centre = (base_half_width + 0.75) * out + cv::Vec3d(0, -0.05, 0);
    const cv::Vec3d t = centre - R * board_centre;
    placements.emplace_back(R(0, 0), R(0, 1), R(0, 2), t[0], R(1, 0), R(1, 1), R(1, 2), t[1], R(2, 0),
                            R(2, 1), R(2, 2), t[2], 0, 0, 0, 1);
  }
  return placements;
}

bool AutoCalibrationReport::allPassed() const {
  return std::all_of(verdicts.begin(), verdicts.end(), [](const StepVerdict& v) { return v.pass; });
}

AutoCalibrationReport runAutoCalibration(const CalibrationRig& rig, const AutoCalibrationConfig& config,
                                         const fs::path& out_dir, std::ostream& log, bool quiet) {
  const int cameras = rig.cameraCount();
  if (static_cast<int>(config.placements.size()) != cameras)
    throw InputError("calibration configuration", "placements", std::to_string(cameras) + " board placements",
                     std::to_string(config.placements.size()));
  fs::create_directories(out_dir);
  AutoCalibrationReport out;
  out.cameras.resize(static_cast<std::size_t>(cameras));

  // 1. Intrinsics, per camera.
  log << "step 1: intrinsics (" << config.intrinsics_board.describe() << ")\n";
  for (int c = 0; c < cameras; ++c) {
    std::vector<BoardView> views;
    std::vector<cv::Mat> drawn;
    std::vector<double> fractions;
    {
      ProgressReporter progress(rig.intrinsicsViewCount(), "camera " + std::to_string(c) + " board photos",
                                quiet);
      for (int v = 0; v < rig.intrinsicsViewCount(); ++v) {
        const cv::Mat photo = rig.intrinsicsPhoto(c, v);
        BoardView view{"view " + std::to_string(v), detectBoard(config.intrinsics_board, photo)};
        if (view.detection.usable()) fractions.push_back(view.detection.widthFraction(photo.cols));
        drawn.push_back(drawDetection(config.intrinsics_board, photo, view.detection));
        views.push_back(std::move(view));
        progress.update();
      }
    }
    savePng(out_dir / ("intrinsics_camera" + std::to_string(c) + ".png"), detectionContactSheet(drawn));
    CameraCalibration& cal = out.cameras[static_cast<std::size_t>(c)];
    cal.serial = rig.serial(c);
    const IntrinsicsResult result =
        calibrateIntrinsics(config.intrinsics_board, views, rig.imageSize(c), "camera " + std::to_string(c));
    cal.intrinsics = result.intrinsics;
    cal.rms = result.rms;
    log << "  camera " << c << " (" << cal.serial << "): fx " << result.intrinsics.fx << " fy "
        << result.intrinsics.fy << " cx " << result.intrinsics.cx << " cy " << result.intrinsics.cy << "\n";
    report(out, log,
           judgeIntrinsics("intrinsics camera " + std::to_string(c), result.rms,
                           static_cast<int>(result.used_views.size()), rig.intrinsicsViewCount(),
                           median(fractions)));
  }

  // 2. Extrinsics: every camera from the board at its marked placement.
  log << "step 2: camera poses (" << config.placement_board.describe() << " at known placements)\n";
  ExtrinsicsProblem problem;
  std::vector<double> placement_fractions;
  for (int c = 0; c < cameras; ++c) {
    problem.cameras.push_back(out.cameras[static_cast<std::size_t>(c)].intrinsics);
    problem.placements.push_back({config.placements[static_cast<std::size_t>(c)], true});
    const cv::Mat photo = rig.placementPhoto(c);
    BoardDetection detection = detectBoard(config.placement_board, photo);
    placement_fractions.push_back(detection.widthFraction(photo.cols));
    savePng(out_dir / ("placement_camera" + std::to_string(c) + ".png"),
            drawDetection(config.placement_board, photo, detection));
    problem.observations.push_back({c, c, std::move(detection)});
  }
  const ExtrinsicsResult poses = calibrateExtrinsics(problem, "board placements");
  for (int c = 0; c < cameras; ++c) {
    out.cameras[static_cast<std::size_t>(c)].T_world_camera =
        toMat4(poses.T_world_camera[static_cast<std::size_t>(c)]);
    const auto& p = poses.T_world_camera[static_cast<std::size_t>(c)];
    log << "  camera " << c << ": position " << p(0, 3) << " " << p(1, 3) << " " << p(2, 3) << " m\n";
    report(out, log,
           judgeExtrinsics("pose camera " + std::to_string(c), poses.camera_rms[static_cast<std::size_t>(c)],
                           poses.camera_corners[static_cast<std::size_t>(c)],
                           placement_fractions[static_cast<std::size_t>(c)]));
  }
  for (const CameraCalibration& cal : out.cameras)
    saveCameraCalibration(cameraCalibrationPath(out_dir, cal.serial), cal);

  // 3. Background, per camera.
  log << "step 3: background (" << config.background_frames << " frames per camera)\n";
  for (int c = 0; c < cameras; ++c) {
    std::vector<RgbdFrame> frames;
    {
      ProgressReporter progress(config.background_frames, "camera " + std::to_string(c) + " background",
                                quiet);
      for (int k = 0; k < config.background_frames; ++k) {
        frames.push_back(rig.backgroundFrame(c, k));
        progress.update();
      }
    }
    const BackgroundModel model = captureBackground(frames, "camera " + std::to_string(c));
    savePng(out_dir / ("background_camera" + std::to_string(c) + ".png"), model.color);
    cv::Mat depth_mm;
    model.depth.convertTo(depth_mm, CV_16U, 1000.0);  // PNG depth in millimetres, 0 = invalid
    savePng(out_dir / ("background_depth_camera" + std::to_string(c) + ".png"), depth_mm);
    log << "  camera " << c << ": " << model.invalid_samples << " invalid depth samples, colour MAD "
        << model.color_mad << "\n";
    report(
        out, log,
        judgeBackground("background camera " + std::to_string(c), model.invalid_fraction, model.color_mad));
  }

  // 4. Panorama yaw: every camera votes; the best-correlated one decides.
  log << "step 4: panorama alignment\n";
  const cv::Mat panorama = rig.panorama();
  YawFit best{0.0f, -2.0};
  for (int c = 0; c < cameras; ++c) {
    const CameraModel model = toCameraModel(out.cameras[static_cast<std::size_t>(c)]);
    const RgbdFrame frame = rig.backgroundFrame(c, 0);
    const YawFit fit = alignPanoramaYaw(panorama, model, frame.color, "camera " + std::to_string(c));
    log << "  camera " << c << ": yaw " << fit.yaw_rad * 180.0f / kPi << " deg, correlation "
        << fit.correlation << "\n";
    if (fit.correlation > best.correlation) best = fit;
  }
  out.pyramid.panorama_yaw_rad = best.yaw_rad;
  out.pyramid.panorama_position = config.panorama_position;
  report(out, log, judgePanorama("panorama yaw", best.correlation));

  // 5. Display alignment, per face.
  log << "step 5: display alignment (test pattern " << config.face_view.width << "x"
      << config.face_view.height << ")\n";
  const auto dots = testPatternDots(config.face_view);
  for (int f = 0; f < kPyramidFaces; ++f) {
    const FaceFit fit = estimateFaceAlignment(dots, rig.observedTestPattern(f, config.face_view),
                                              config.face_view, "face " + std::to_string(f));
    out.pyramid.faces[static_cast<std::size_t>(f)] = fit.alignment;
    cv::Mat shown;
    cv::warpAffine(drawTestPattern(config.face_view, f), shown,
                   cv::Mat(faceTransform(fit.alignment, config.face_view)), config.face_view);
    savePng(out_dir / ("display_face" + std::to_string(f) + ".png"), shown);
    log << "  face " << f << ": offset " << fit.alignment.offset_px.x << " " << fit.alignment.offset_px.y
        << " px, scale " << fit.alignment.scale << ", rotation " << fit.alignment.rotation_deg << " deg"
        << (fit.alignment.mirror ? ", mirrored" : "") << "\n";
    report(out, log, judgeDisplay("display face " + std::to_string(f), fit.residual_px));
  }
  savePyramidCalibration(pyramidCalibrationPath(out_dir), out.pyramid);
  log << (out.allPassed() ? "calibration complete: every step passed\n"
                          : "calibration saved, but some steps failed: see the hints above\n");
  return out;
}

}  // namespace holo::calib
