// `holopyramid calibrate`: the calibration steps without a window, and the wizard window
// (`calibrate wizard`, cmd_calibrate_wizard.cpp).
//   holopyramid calibrate intrinsics --images 'GLOB' --board SPEC --out FILE.yml
// calibrates one camera from photos of a board, prints fx, fy, cx, cy and the RMS reprojection
// error with a pass/fail verdict, and writes FILE.yml (atomically, the old one kept as .bak)
// and FILE.corners.png (every photo with its detected corners).
//   holopyramid calibrate stereo --left 'GLOB' --right 'GLOB' --board SPEC --out FILE.yml
// calibrates a stereo pair from two photo sets: both cameras' intrinsics, their relative pose and
// its loop closure, FILE.yml and FILE.png (the first pair rectified, with epipolar lines).

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "command.hpp"
#include "holo/calib/auto_calibration.hpp"
#include "holo/calib/board.hpp"
#include "holo/calib/calibration_io.hpp"
#include "holo/calib/capture_rig.hpp"
#include "holo/calib/intrinsics.hpp"
#include "holo/calib/pose.hpp"
#include "holo/calib/quality.hpp"
#include "holo/calib/stereo_calibration.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/log.hpp"
#include "holo/core/progress.hpp"
#include "holo/simulated/simulated_rig.hpp"
#include "holo/simulated/simulated_source.hpp"

namespace holo::app {
namespace {

namespace fs = std::filesystem;

// A serial usable as camera_name: the output file's stem, reduced to the allowed characters.
std::string serialFromPath(const fs::path& out) {
  std::string serial = out.stem().string();
  for (auto& ch : serial)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_' && ch != '.') ch = '_';
  return serial.empty() ? "camera" : serial;
}

struct IntrinsicsOptions {
  std::string images;
  std::string board;
  std::string out;
  std::string serial;
  bool quiet = false;
};

int runIntrinsics(const IntrinsicsOptions& options) {
  const calib::BoardSpec board = calib::BoardSpec::parse(options.board);
  const std::vector<std::string> files = calib::PhotoSource::expand(options.images);
  std::vector<calib::BoardView> views;
  std::vector<cv::Mat> drawn;
  std::vector<double> fractions;
  cv::Size size;
  {
    ProgressReporter progress(static_cast<std::int64_t>(files.size()), "detecting " + board.describe(),
                              options.quiet);
    for (const std::string& file : files) {
      const cv::Mat image = cv::imread(file, cv::IMREAD_COLOR);
      progress.update();
      if (image.empty()) {
        HOLO_LOG_WARN("{}: not a readable image, skipped", file);
        continue;
      }
      if (size.area() == 0) size = image.size();
      if (image.size() != size)
        throw InputError(
            file, "image size",
            std::to_string(size.width) + "x" + std::to_string(size.height) + " like " + files.front(),
            std::to_string(image.cols) + "x" + std::to_string(image.rows));
      calib::BoardView view{fs::path(file).filename().string(), calib::detectBoard(board, image)};
      if (view.detection.usable()) fractions.push_back(view.detection.widthFraction(image.cols));
      drawn.push_back(calib::drawDetection(board, image, view.detection));
      views.push_back(std::move(view));
    }
  }
  const calib::IntrinsicsResult result = calib::calibrateIntrinsics(board, views, size, options.images);

  const fs::path out = options.out;
  calib::CameraCalibration calibration;
  // Recalibrating intrinsics keeps a pose calibrated earlier.
  if (fs::exists(out)) {
    try {
      calibration = calib::loadCameraCalibration(out);
    } catch (const InputError& e) {
      HOLO_LOG_WARN("{}: previous calibration unreadable ({}); its pose is not kept", out.string(), e.what());
    }
  }
  calibration.serial = !options.serial.empty()       ? options.serial
                       : !calibration.serial.empty() ? calibration.serial
                                                     : serialFromPath(out);
  calibration.intrinsics = result.intrinsics;
  calibration.rms = result.rms;
  calibration.date.clear();
  calib::saveCameraCalibration(out, calibration);

  fs::path sheet_path = out;
  sheet_path.replace_extension(".corners.png");
  const cv::Mat sheet = calib::detectionContactSheet(drawn);
  writeAtomically(sheet_path, [&](const fs::path& tmp) {
    if (!cv::imwrite(tmp.string(), sheet)) throw Error("could not write " + tmp.string());
  });

  std::sort(fractions.begin(), fractions.end());
  const double median_fraction = fractions.empty() ? 0.0 : fractions[fractions.size() / 2];
  const calib::StepVerdict verdict = calib::judgeIntrinsics("intrinsics " + calibration.serial, result.rms,
                                                            static_cast<int>(result.used_views.size()),
                                                            static_cast<int>(files.size()), median_fraction);
  const Intrinsics& K = result.intrinsics;
  std::cout << std::fixed << std::setprecision(3) << "camera: " << calibration.serial << "\n"
            << "board: " << board.describe() << "\n"
            << "views: " << result.used_views.size() << " of " << files.size() << "\n"
            << "image: " << K.width << "x" << K.height << "\n"
            << "fx: " << K.fx << "\nfy: " << K.fy << "\ncx: " << K.cx << "\ncy: " << K.cy << "\n"
            << "distortion: " << K.distortion[0] << " " << K.distortion[1] << " " << K.distortion[2] << " "
            << K.distortion[3] << " " << K.distortion[4] << "\n"
            << "rms: " << result.rms << " px\n";
  for (std::size_t i = 0; i < result.used_views.size(); ++i)
    std::cout << "  " << result.used_views[i] << ": " << result.view_rms[i] << " px\n";
  for (const auto& name : result.skipped_views) std::cout << "  " << name << ": board not found, skipped\n";
  std::cout << "saved: " << out.string() << "\ncorners: " << sheet_path.string() << "\n"
            << calib::formatVerdict(verdict) << "\n";
  return verdict.pass ? 0 : 3;
}

struct StereoOptions {
  std::string left;
  std::string right;
  std::string board;
  std::string out;
  bool quiet = false;
};

int runStereo(const StereoOptions& options) {
  const calib::BoardSpec board = calib::BoardSpec::parse(options.board);
  const calib::StereoCalibration s =
      calib::calibrateStereoPhotos(options.left, options.right, board, std::cout, options.quiet);
  const fs::path out = options.out;
  calib::saveStereoCalibration(out, s);
  fs::path picture_path = out;
  picture_path.replace_extension(".png");
  writeAtomically(picture_path, [&](const fs::path& tmp) {
    if (!cv::imwrite(tmp.string(), s.picture)) throw Error("could not write " + tmp.string());
  });
  cv::Vec3d rvec, tvec;
  calib::poseToRt(s.pose.T_a_b, rvec, tvec);
  const auto camera = [](const char* name, const calib::CameraCalibration& c) {
    const Intrinsics& K = c.intrinsics;
    std::cout << name << ": fx " << K.fx << " fy " << K.fy << " cx " << K.cx << " cy " << K.cy
              << ", distortion " << K.distortion[0] << " " << K.distortion[1] << " " << K.distortion[2] << " "
              << K.distortion[3] << " " << K.distortion[4] << ", RMS " << c.rms << " px\n";
  };
  std::cout << std::fixed << std::setprecision(3);
  camera("left", s.left);
  camera("right", s.right);
  std::cout << "pairs: " << s.pose.pairs << " of " << s.left_files.size() << " with the board in both\n"
            << "right camera in the left frame: " << tvec * 1000.0 << " mm (baseline " << s.baseline_mm
            << " mm), rotation " << s.rotation_deg << " deg\n"
            << "rms: " << s.pose.rms_px << " px (both cameras, joint adjustment)\n"
            << "loop closure per pair: median " << s.loop_median_mm << " mm / " << s.loop_median_deg
            << " deg, worst " << s.loop_worst_mm << " mm / " << s.loop_worst_deg << " deg\n"
            << "cv::stereoCalibrate (intrinsics fixed): rms " << s.opencv_rms_px << " px, "
            << s.opencv_difference_mm << " mm / " << s.opencv_difference_deg << " deg from the joint pose\n"
            << "rectified rows of corresponding corners: median " << s.rectified_row_median_px
            << " px, worst " << s.rectified_row_worst_px << " px\n"
            << "saved: " << out.string() << "\nrectified pair: " << picture_path.string() << "\n";
  bool pass = true;
  for (const calib::StepVerdict& verdict : s.verdicts) {
    std::cout << calib::formatVerdict(verdict) << "\n";
    pass = pass && verdict.pass;
  }
  return pass ? 0 : 3;
}

struct AutoOptions {
  bool enabled = false;
  std::string scene = "museum";
  std::string config;
  std::string out;
  std::string intrinsics_board = calib::kDefaultIntrinsicsBoard;
  std::string placement_board = calib::kDefaultPlacementBoard;
  int background_frames = 9;
  bool quiet = false;
};

// Prints how far the calibration is from `truth` (the simulation's, or a recording's models).
void printTruthCheck(const calib::AutoCalibrationReport& report, const std::vector<CameraModel>& truth) {
  for (std::size_t c = 0; c < truth.size() && c < report.cameras.size(); ++c) {
    const auto& got = report.cameras[c];
    const cv::Matx44d pose = calib::toMatx(got.T_world_camera),
                      want = calib::toMatx(truth[c].T_world_camera());
    std::cout << "  camera " << c << ": fx " << got.intrinsics.fx << " (true " << truth[c].intrinsics().fx
              << ", " << 100.0 * (got.intrinsics.fx / truth[c].intrinsics().fx - 1.0)
              << " %), position error " << calib::translationError(pose, want) * 1000.0
              << " mm, rotation error " << calib::rotationErrorDeg(pose, want) << " deg\n";
  }
}

// --auto on the simulated museum (whose truth it also prints, so a run can be checked at a
// glance), or with --config on the cameras of a configuration's capture: section.
int runAuto(const AutoOptions& options) {
  const calib::AutoCalibrationConfig base =
      calibrationConfig(options.intrinsics_board, options.placement_board, options.background_frames);
  if (!options.config.empty()) {
    calib::ConfiguredRig configured =
        calib::loadConfiguredRig(options.config, simulated::configuredSources());
    calib::AutoCalibrationConfig config = base;
    config.placements = calib::defaultBoardPlacements(config.placement_board, configured.rig->cameraCount());
    const fs::path out = options.out.empty() ? configured.calibration_dir : fs::path(options.out);
    std::cout << "calibrating " << configured.rig->describe() << " into " << out.string() << "\n";
    const calib::AutoCalibrationReport report =
        calib::runAutoCalibration(*configured.rig, config, out, std::cout, options.quiet);
    std::vector<CameraModel> truth;
    for (int c = 0; c < configured.rig->cameraCount(); ++c)
      if (const auto model = configured.rig->sourceModel(c)) truth.push_back(*model);
    if (report.saved && static_cast<int>(truth.size()) == configured.rig->cameraCount()) {
      std::cout << "check against the models the sources carry (a recording's truth):\n";
      printTruthCheck(report, truth);
    }
    return report.saved ? 0 : 3;
  }
  simulated::SimulatedRig rig(options.scene, base);
  const fs::path out = options.out.empty() ? fs::path("calibration") : fs::path(options.out);
  std::cout << "calibrating the simulated museum (scene " << options.scene << ") into " << out.string()
            << "\n";
  const calib::AutoCalibrationReport report =
      calib::runAutoCalibration(rig, base, out, std::cout, options.quiet);
  if (!report.saved) return 3;
  std::cout << "truth check (simulation):\n";
  std::vector<CameraModel> truth;
  for (int c = 0; c < rig.cameraCount(); ++c) truth.push_back(rig.trueCamera(c));
  printTruthCheck(report, truth);
  std::cout << "  panorama yaw " << report.pyramid.panorama_yaw_rad * 180.0f / kPi << " deg (true "
            << rig.truePanoramaYaw() * 180.0f / kPi << ")\n";
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "calibrate",
    [](CLI::App& sub) {
      auto intrinsics = std::make_shared<IntrinsicsOptions>();
      CLI::App* intr =
          sub.add_subcommand("intrinsics", "Calibrate one camera's intrinsics from photos of a board");
      intr->add_option("--images", intrinsics->images, "Photos, as a quoted glob ('photos/left*.jpg')")
          ->required();
      intr->add_option("--board", intrinsics->board,
                       "chessboard:COLSxROWS:SQUARE_M (inner corners) or "
                       "charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT (squares)")
          ->required();
      intr->add_option("--out", intrinsics->out, "Calibration file to write (FileStorage YAML)")->required();
      intr->add_option("--serial", intrinsics->serial,
                       "Camera serial (default: kept from --out, else its name)");
      intr->add_flag("--quiet", intrinsics->quiet, "No progress output");
      auto stereo = std::make_shared<StereoOptions>();
      CLI::App* st = sub.add_subcommand(
          "stereo", "Calibrate a stereo pair from two photo sets (photo k of each taken at the same moment)");
      st->add_option("--left", stereo->left, "Left camera's photos, as a quoted glob ('photos/left*.jpg')")
          ->required();
      st->add_option("--right", stereo->right,
                     "Right camera's photos, as many as --left, paired in sorted order")
          ->required();
      st->add_option("--board", stereo->board,
                     "chessboard:COLSxROWS:SQUARE_M (inner corners) or "
                     "charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT (squares)")
          ->required();
      st->add_option("--out", stereo->out,
                     "Stereo calibration to write (FileStorage YAML; FILE.png beside it)")
          ->required();
      st->add_flag("--quiet", stereo->quiet, "No progress output");
      auto automatic = std::make_shared<AutoOptions>();
      sub.add_flag("--auto", automatic->enabled,
                   "Run every step without a window (on the simulated museum, or the cameras of --config)");
      sub.add_option("--config", automatic->config,
                     "YAML configuration: calibrate the cameras of its capture: section (--auto)");
      sub.add_option("--scene", automatic->scene, "Simulated scene for --auto without --config")
          ->capture_default_str();
      sub.add_option("--out", automatic->out,
                     "Folder for the calibration files (--auto; default: capture.calibration_dir of "
                     "--config, else calibration)");
      sub.add_option("--intrinsics-board", automatic->intrinsics_board, "Board for intrinsics (--auto)")
          ->capture_default_str();
      sub.add_option("--placement-board", automatic->placement_board,
                     "Board at the marked placements (--auto)")
          ->capture_default_str();
      sub.add_option("--background-frames", automatic->background_frames, "Frames per background (--auto)")
          ->capture_default_str();
      sub.add_flag("--quiet", automatic->quiet, "No progress output");
      const WizardSubcommand wizard = addWizardSubcommand(sub);
      return std::function<int()>([intr, intrinsics, st, stereo, automatic, wizard, parent = &sub]() -> int {
        if (intr->parsed()) return runIntrinsics(*intrinsics);
        if (st->parsed()) return runStereo(*stereo);
        if (wizard.app->parsed()) return wizard.run();
        if (automatic->enabled) return runAuto(*automatic);
        std::cerr << parent->help();
        return 2;
      });
    },
    "Calibrate cameras, panorama and display (subcommands; wizard opens the window, --auto runs every "
    "step)"});

}  // namespace holo::app
