// Calibration on frames as cameras deliver them (calib::CaptureRig over capture sources): OpenCV's
// real stereo photos through a photo folder per camera, the same steps the live cameras run.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "board_poses.hpp"
#include "holo/calib/calibration_session.hpp"
#include "holo/calib/capture_rig.hpp"
#include "holo/calib/extrinsics.hpp"
#include "holo/calib/pose.hpp"
#include "holo/calib/synthetic_board.hpp"
#include "holo/core/error.hpp"
#include "holo/core/median.hpp"
#include "shared_data.hpp"

namespace holo::calib {
namespace {

namespace fs = std::filesystem;

AutoCalibrationConfig chessboardConfig(int cameras) {
  AutoCalibrationConfig config;
  config.intrinsics_board = BoardSpec::parse("chessboard:9x6:0.025");
  config.placement_board = config.intrinsics_board;
  config.placements = defaultBoardPlacements(config.placement_board, cameras);
  return config;
}

// Both cameras of ../shared/data/calib/chessboard_9x6 (left and right photo folders) through
// the intrinsics step; left within 1% of OpenCV's reference; the pair's relative pose from the
// photos in which both saw the board, with its loop closure.
TEST(CaptureRig, RealStereoPhotosThroughTheLiveIntrinsicsStep) {
  HOLO_REQUIRE_SHARED_DATA("calib/chessboard_9x6/left_intrinsics.yml");
  const fs::path dir = holo::test::sharedData("calib/chessboard_9x6");
  std::vector<std::unique_ptr<capture::CameraSource>> sources;
  for (const char* side : {"left", "right"})
    sources.push_back(std::make_unique<PhotoSource>(
        side, PhotoSource::expand((dir / (std::string(side) + "[0-9]*.jpg")).string())));
  CaptureRig rig(std::move(sources), cv::Mat(), {}, "OpenCV's stereo photos", /*stills=*/true);
  ASSERT_EQ(rig.imageSize(0), cv::Size(640, 480));
  CalibrationSession session(rig, chessboardConfig(2));
  std::ostringstream log;
  const StepOutcome& outcome = session.measure(CalibrationStep::Intrinsics, log);
  std::cout << log.str();
  ASSERT_TRUE(outcome.error.empty()) << outcome.error;
  ASSERT_EQ(outcome.verdicts.size(), 4u);  // intrinsics and colour gains of each (photos have no depth)
  EXPECT_TRUE(outcome.passed());

  cv::FileStorage reference((dir / "left_intrinsics.yml").string(), cv::FileStorage::READ);
  cv::Mat K;
  reference["camera_matrix"] >> K;
  const double fx_ref = K.at<double>(0, 0);
  const Intrinsics left = session.report().cameras[0].intrinsics,
                   right = session.report().cameras[1].intrinsics;
  std::cout << "left fx " << left.fx << " fy " << left.fy << " (reference " << fx_ref << "), right fx "
            << right.fx << " fy " << right.fy << "\n";
  EXPECT_NEAR(left.fx, fx_ref, 0.01 * fx_ref);
  EXPECT_NEAR(left.fy, fx_ref, 0.01 * fx_ref);
  // The two cameras of the pair are alike (the same model of camera and lens).
  EXPECT_NEAR(right.fx, left.fx, 0.02 * left.fx);
  // Every photo shows the board: every one is a view (stills are not compared for motion).
  const auto& left_obs = session.boardObservations(CalibrationStep::Intrinsics, 0);
  const auto& right_obs = session.boardObservations(CalibrationStep::Intrinsics, 1);
  ASSERT_EQ(left_obs.size(), 13u);
  ASSERT_EQ(right_obs.size(), 13u);
  EXPECT_TRUE(left_obs[0].T_camera_board.has_value());

  // Photo k of each folder was taken at the same moment (left01 with right01, ...).
  std::vector<SharedBoardView> shared;
  for (std::size_t k = 0; k < left_obs.size(); ++k)
    if (left_obs[k].detection.usable() && right_obs[k].detection.usable())
      shared.push_back({left_obs[k].detection, right_obs[k].detection});
  const RelativePose pair = relativePoseFromSharedViews(left, right, shared, "stereo pair");
  const double baseline_mm =
      1000.0 * std::sqrt(pair.T_a_b(0, 3) * pair.T_a_b(0, 3) + pair.T_a_b(1, 3) * pair.T_a_b(1, 3) +
                         pair.T_a_b(2, 3) * pair.T_a_b(2, 3));
  cv::Vec3d rvec, tvec;
  poseToRt(pair.T_a_b, rvec, tvec);
  const double worst_mm = *std::max_element(pair.pair_translation_mm.begin(), pair.pair_translation_mm.end());
  const double worst_deg = *std::max_element(pair.pair_rotation_deg.begin(), pair.pair_rotation_deg.end());
  std::cout << "stereo: " << pair.pairs << " pairs, right camera at " << tvec * 1000.0
            << " mm in the left frame "
            << "(baseline " << baseline_mm << " mm), rotation " << cv::norm(rvec) * 180.0 / CV_PI
            << " deg, joint RMS " << pair.rms_px << " px; loop closure per pair: median "
            << median(pair.pair_translation_mm) << " mm / " << median(pair.pair_rotation_deg)
            << " deg, worst " << worst_mm << " mm / " << worst_deg << " deg\n";
  EXPECT_EQ(pair.pairs, 13);
  EXPECT_LT(pair.rms_px, 0.5);
  // A side-by-side pair: the right camera sits along the left one's x axis.
  EXPECT_GT(std::abs(tvec[0]), 5.0 * std::max(std::abs(tvec[1]), std::abs(tvec[2])));
  EXPECT_LT(median(pair.pair_translation_mm), 2.0);
  EXPECT_LT(median(pair.pair_rotation_deg), 0.5);
}

// A camera that delivers nothing is refused before any step runs, naming it.
TEST(CaptureRig, EmptyPhotoFolderIsAMissingCamera) {
  const fs::path dir = holo::test::scratchDir("calib_capture_rig_empty");
  std::vector<std::unique_ptr<capture::CameraSource>> sources;
  sources.push_back(std::make_unique<PhotoSource>("cam0", std::vector<std::string>{}));
  try {
    CaptureRig rig(std::move(sources), cv::Mat(), {}, "no photos", true);
    FAIL() << "a camera without frames was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("photos:cam0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
  EXPECT_THROW(PhotoSource::expand((dir / "*.jpg").string()), InputError);
}

// Two cameras side by side (0.3 m apart, both looking along +Z, 640x480, 80 degrees wide), so the
// easel at each camera's marked spot is seen by both at once: the poses step's loop closure. The
// boards stand at `true_spots` (the technician's real placement) while the configuration holds
// the marked spots. Frames: the intrinsics board at 12 held poses (a moving frame before each),
// then the easel at each spot for 3 frames with 2 frames between spots.
class SideBySideRig : public CalibrationRig {
 public:
  SideBySideRig(const AutoCalibrationConfig& config, std::vector<cv::Matx44d> true_spots)
      : config_(config),
        true_spots_(std::move(true_spots)),
        intrinsics_texture_(renderBoardTexture(config.intrinsics_board, 60)),
        placement_texture_(renderBoardTexture(config.placement_board, 60)) {
    K_ = Intrinsics::fromFov(640, 480, 80.0f * kPi / 180.0f, 63.0f * kPi / 180.0f);
    K_.distortion = {-0.05f, 0.01f, 0.0f, 0.0f, 0.0f};
  }
  cv::Matx44d trueCamera(int camera) const {
    return {1, 0, 0, 0.3 * camera, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  }
  const Intrinsics& intrinsics() const { return K_; }

  int cameraCount() const override { return 2; }
  std::string serial(int camera) const override { return camera == 0 ? "left" : "right"; }
  cv::Size imageSize(int) const override { return {640, 480}; }
  std::string describe() const override { return "two cameras side by side"; }
  void begin(RigActivity activity) override {
    activity_ = activity;
    next_ = {0, 0};
  }
  std::optional<RgbdFrame> nextFrame(int camera) override {
    const int index = next_[static_cast<std::size_t>(camera)]++;
    SyntheticViewOptions options;
    options.seed = static_cast<std::uint64_t>(100 * camera + index +
                                              (activity_ == RigActivity::PlacementBoard ? 50 : 0));
    RgbdFrame frame;
    frame.device_time = Nanoseconds(index);
    cv::Mat grey;
    if (activity_ == RigActivity::HandHeldBoard) {
      constexpr int kPoses = 12;
      if (index >= 3 * kPoses + 3) return std::nullopt;
      if (index >= 3 * kPoses) {
        grey = cv::Mat(480, 640, CV_8UC1, cv::Scalar(90));
      } else {
        // Six places in the picture, each at two tilts.
        const int pose = index / 3;
        const double x = 0.1 * (pose % 3 - 1), y = (pose / 3) % 2 ? 0.07 : -0.07;
        const double tilt_x = pose < 6 ? 20.0 : -20.0, tilt_y = pose % 2 ? 25.0 : -25.0;
        const double moving = index % 3 == 0 ? 0.03 : 0.0;  // on the way there: not yet still
        grey = renderBoardView(intrinsics_texture_, K_,
                               test::boardPose(config_.intrinsics_board, tilt_x, tilt_y, 10.0 * pose,
                                               {x + moving, y, 0.45 + 0.03 * (pose % 4)}),
                               options);
      }
    } else if (activity_ == RigActivity::PlacementBoard) {
      const int spot = index / 5;
      if (spot >= 2) return std::nullopt;
      grey = index % 5 < 3 ? renderBoardView(placement_texture_, K_,
                                             rigidInverse(trueCamera(camera)) *
                                                 true_spots_[static_cast<std::size_t>(spot)],
                                             options)
                           : cv::Mat(480, 640, CV_8UC1, cv::Scalar(90));
    } else {
      return std::nullopt;
    }
    cv::cvtColor(grey, frame.colour, cv::COLOR_GRAY2BGR);
    return frame;
  }
  cv::Mat panorama() const override { return {}; }
  std::vector<cv::Point2f> observedTestPattern(int, cv::Size) const override { return {}; }

 private:
  AutoCalibrationConfig config_;
  std::vector<cv::Matx44d> true_spots_;
  BoardTexture intrinsics_texture_, placement_texture_;
  Intrinsics K_;
  RigActivity activity_ = RigActivity::HandHeldBoard;
  std::array<int, 2> next_{0, 0};
};

// Both cameras see each easel spot: the loop closure agrees when the boards stood on their
// spots, and exposes a board 2 cm off its spot (which shifts that camera's pose).
TEST(CaptureRig, LoopClosureWhereTwoCamerasSeeTheBoard) {
  AutoCalibrationConfig config;
  config.intrinsics_board = BoardSpec::parse(kDefaultIntrinsicsBoard);
  config.placement_board = BoardSpec::parse("charuco:7x5:0.08:0.05:DICT_5X5_100");
  // The marked spots: 1.2 m ahead, between the cameras, each turned towards its camera.
  for (int spot = 0; spot < 2; ++spot)
    config.placements.push_back(test::boardPose(config.placement_board, 10.0, spot == 0 ? 15.0 : -15.0, 0.0,
                                                {0.15 + (spot == 0 ? -0.05 : 0.05), 0.0, 1.2}));
  const auto run = [&](std::vector<cv::Matx44d> true_spots) {
    SideBySideRig rig(config, std::move(true_spots));
    CalibrationSession session(rig, config);
    std::ostringstream log;
    session.measure(CalibrationStep::Intrinsics, log);
    const StepOutcome poses = session.measure(CalibrationStep::Poses, log);
    std::cout << log.str();
    EXPECT_TRUE(poses.error.empty()) << poses.error;
    return std::make_pair(session.loopClosures(), poses);
  };
  const auto [good, good_outcome] = run(config.placements);
  ASSERT_EQ(good.size(), 2u);  // each spot was seen by the other camera too
  // Single boards 1.2 m away pin each camera to a few mm (measured 3.7 and 4.8 mm, 0.18 and 0.23
  // degrees); a board 2 cm off its spot shows as 18-19 mm.
  for (const LoopClosure& l : good) {
    EXPECT_LT(l.translation_mm, 7.0);
    EXPECT_LT(l.rotation_deg, 0.3);
  }
  EXPECT_TRUE(good_outcome.passed());

  std::vector<cv::Matx44d> moved = config.placements;
  moved[1](0, 3) += 0.02;  // the easel stood 2 cm to the side of camera 1's spot
  const auto [bad, bad_outcome] = run(moved);
  ASSERT_EQ(bad.size(), 2u);
  for (const LoopClosure& l : bad) EXPECT_GT(l.translation_mm, 15.0);
  EXPECT_FALSE(bad_outcome.passed());
}

}  // namespace
}  // namespace holo::calib
