// The verification step's alignment figure: the verification jig's printed squares projected
// through a camera's pose against the edges of its picture. On the simulated museum (the jig
// rendered into each camera's frame) the true pose passes and a pose 1 cm or 1 degree off is
// caught, with the measured pose error near the perturbation; on real photos (OpenCV's chessboard
// sample, the board's pose from its corners) the same holds for the board's square edges.
#include <gtest/gtest.h>

#include <iostream>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/calib/edge_alignment.hpp"
#include "holo/calib/pose.hpp"
#include "holo/calib/quality.hpp"
#include "holo/calib/verification_target.hpp"
#include "holo/simulated/simulated_rig.hpp"
#include "shared_data.hpp"

namespace holo::calib {
namespace {

// The camera moved by `delta` in its own frame (rotation vector in radians, then metres).
CameraModel perturbed(const CameraModel& camera, const cv::Vec3d& rotation, const cv::Vec3d& translation) {
  const cv::Matx44d T = toMatx(camera.T_world_camera()) * poseFromRt(rotation, translation);
  return CameraModel(camera.intrinsics(), toMat4(T));
}

struct Perturbation {
  const char* what;
  cv::Vec3d rotation, translation;
};

std::vector<Perturbation> perturbations() {
  const double cm = 0.01, deg = CV_PI / 180.0;
  return {{"1 cm right", {0, 0, 0}, {cm, 0, 0}},    {"1 cm down", {0, 0, 0}, {0, cm, 0}},
          {"1 cm forward", {0, 0, 0}, {0, 0, cm}},  {"1 degree tilt", {deg, 0, 0}, {0, 0, 0}},
          {"1 degree pan", {0, deg, 0}, {0, 0, 0}}, {"1 degree roll", {0, 0, deg}, {0, 0, 0}}};
}

TEST(EdgeAlignment, SimulatedJigPassesTheTruePoseAndCatchesOneCentimetreOrOneDegree) {
  AutoCalibrationConfig config;
  config.intrinsics_board = BoardSpec::parse(kDefaultIntrinsicsBoard);
  config.placement_board = BoardSpec::parse(kDefaultPlacementBoard);
  config.placements = defaultBoardPlacements(config.placement_board, sim::kFaceCount);
  config.background_frames = 1;
  simulated::SimulatedRig rig("museum", config);
  for (int c = 0; c < rig.cameraCount(); ++c) {
    const RgbdFrame frame = rig.frame(RigActivity::VerificationJig, c, 0);
    const std::vector<EdgeSegment> edges = verificationTargetEdges(verificationTargetPose(c));
    const CameraModel& truth = rig.trueCamera(c);
    const EdgeAlignment good =
        measureEdgeAlignment(frame.colour, truth, edges, "camera " + std::to_string(c));
    std::cout << "camera " << c << " true pose: chamfer " << good.chamfer_px << " px -> "
              << good.chamfer_aligned_px << " px, pose error " << good.position_error_mm << " mm "
              << good.rotation_error_deg << " deg, seen " << good.seen_fraction << "\n";
    EXPECT_TRUE(judgeVerification("camera", good).pass) << formatVerdict(judgeVerification("camera", good));
    for (const Perturbation& p : perturbations()) {
      const EdgeAlignment bad = measureEdgeAlignment(
          frame.colour, perturbed(truth, p.rotation, p.translation), edges, "camera " + std::to_string(c));
      std::cout << "  " << p.what << ": chamfer " << bad.chamfer_px << " px -> " << bad.chamfer_aligned_px
                << " px, pose error " << bad.position_error_mm << " mm " << bad.rotation_error_deg
                << " deg\n";
      EXPECT_FALSE(judgeVerification("camera", bad).pass) << "camera " << c << ", " << p.what;
      EXPECT_GT(bad.chamfer_px, good.chamfer_px + 0.3) << "camera " << c << ", " << p.what;
      // The pose error is the perturbation, measured: within 30 % of it.
      if (cv::norm(p.translation) > 0)
        EXPECT_NEAR(bad.position_error_mm, 10.0, 3.0) << "camera " << c << ", " << p.what;
      else
        EXPECT_NEAR(bad.rotation_error_deg, 1.0, 0.3) << "camera " << c << ", " << p.what;
    }
  }
}

// An adversary: without the jig in the picture no edge is where the calibration puts them; the
// truncated distances cannot move the pose, so a figure of the pose error alone would pass it.
TEST(EdgeAlignment, JigMissingFails) {
  AutoCalibrationConfig config;
  config.intrinsics_board = BoardSpec::parse(kDefaultIntrinsicsBoard);
  config.placement_board = BoardSpec::parse(kDefaultPlacementBoard);
  config.placements = defaultBoardPlacements(config.placement_board, sim::kFaceCount);
  config.background_frames = 1;
  simulated::SimulatedRig rig("museum", config);
  const RgbdFrame hall = rig.frame(RigActivity::EmptyHall, 0, 0);
  const EdgeAlignment a = measureEdgeAlignment(
      hall.colour, rig.trueCamera(0), verificationTargetEdges(verificationTargetPose(0)), "camera 0");
  std::cout << "no jig: chamfer " << a.chamfer_px << " px -> " << a.chamfer_aligned_px << " px\n";
  const StepVerdict verdict = judgeVerification("camera 0", a);
  EXPECT_FALSE(verdict.pass);
  EXPECT_NE(verdict.hint.find("not found"), std::string::npos) << verdict.hint;
  // A pose turned away from the jig shows none of it: its samples count as misses, not as nothing.
  const EdgeAlignment away =
      measureEdgeAlignment(rig.frame(RigActivity::VerificationJig, 0, 0).colour,
                           perturbed(rig.trueCamera(0), {0, CV_PI, 0}, {0, 0, 0}),
                           verificationTargetEdges(verificationTargetPose(0)), "camera 0");
  EXPECT_DOUBLE_EQ(away.chamfer_px, kEdgeTruncationPx);
  EXPECT_FALSE(judgeVerification("camera 0", away).pass);
}

// Real photos: OpenCV's chessboard sample with OpenCV's own calibration of that camera. The
// board's pose from its corners is the correct pose; the edges are the board's inner grid lines.
TEST(EdgeAlignment, RealChessboardPhotosPassTheirPoseAndCatchOneCentimetreOrOneDegree) {
  HOLO_REQUIRE_SHARED_DATA("calib/chessboard_9x6/left_intrinsics.yml");
  const auto dir = holo::test::sharedData("calib/chessboard_9x6");
  cv::FileStorage fs((dir / "left_intrinsics.yml").string(), cv::FileStorage::READ);
  cv::Matx33d K;
  cv::Mat distortion;
  fs["camera_matrix"] >> K;
  fs["distortion_coefficients"] >> distortion;
  const double square = static_cast<double>(fs["square_size"]);
  Intrinsics intrinsics;
  intrinsics.width = 640;
  intrinsics.height = 480;
  intrinsics.fx = static_cast<float>(K(0, 0));
  intrinsics.fy = static_cast<float>(K(1, 1));
  intrinsics.cx = static_cast<float>(K(0, 2));
  intrinsics.cy = static_cast<float>(K(1, 2));
  for (int i = 0; i < 5; ++i)
    intrinsics.distortion[static_cast<std::size_t>(i)] = static_cast<float>(distortion.at<double>(i));
  const cv::Size pattern(9, 6);
  std::vector<cv::Point3d> corners3d;
  for (int j = 0; j < pattern.height; ++j)
    for (int i = 0; i < pattern.width; ++i) corners3d.emplace_back(i * square, j * square, 0.0);
  std::vector<EdgeSegment> grid;
  for (int j = 0; j < pattern.height; ++j)
    for (int i = 0; i < pattern.width; ++i) {
      const cv::Point3d p(i * square, j * square, 0.0);
      if (i + 1 < pattern.width) grid.push_back({p, p + cv::Point3d(square, 0, 0)});
      if (j + 1 < pattern.height) grid.push_back({p, p + cv::Point3d(0, square, 0)});
    }
  for (const char* name : {"left01.jpg", "left03.jpg", "left06.jpg"}) {
    const cv::Mat colour = cv::imread((dir / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(colour.empty()) << name;
    cv::Mat grey;
    cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
    std::vector<cv::Point2f> found;
    ASSERT_TRUE(cv::findChessboardCorners(grey, pattern, found)) << name;
    cv::cornerSubPix(grey, found, cv::Size(11, 11), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS | cv::TermCriteria::COUNT, 30, 0.01));
    cv::Vec3d rvec, tvec;
    ASSERT_TRUE(cv::solvePnP(corners3d, found, K, distortion, rvec, tvec));
    const CameraModel camera(intrinsics, toMat4(rigidInverse(poseFromRt(rvec, tvec))));
    const EdgeAlignment good = measureEdgeAlignment(colour, camera, grid, name);
    std::cout << name << " (board " << tvec[2] << " m away): chamfer " << good.chamfer_px << " px -> "
              << good.chamfer_aligned_px << " px, pose error " << good.position_error_mm << " mm "
              << good.rotation_error_deg << " deg\n";
    EXPECT_TRUE(judgeVerification(name, good).pass) << formatVerdict(judgeVerification(name, good));
    for (const Perturbation& p : perturbations()) {
      const EdgeAlignment bad =
          measureEdgeAlignment(colour, perturbed(camera, p.rotation, p.translation), grid, name);
      std::cout << "  " << p.what << ": chamfer " << bad.chamfer_px << " px -> " << bad.chamfer_aligned_px
                << " px, pose error " << bad.position_error_mm << " mm " << bad.rotation_error_deg
                << " deg\n";
      EXPECT_FALSE(judgeVerification(name, bad).pass) << name << ", " << p.what;
      EXPECT_GT(bad.chamfer_px, good.chamfer_px + 0.3) << name << ", " << p.what;
      if (cv::norm(p.translation) > 0)
        EXPECT_NEAR(bad.position_error_mm, 10.0, 3.0) << name << ", " << p.what;
      else
        EXPECT_NEAR(bad.rotation_error_deg, 1.0, 0.3) << name << ", " << p.what;
    }
  }
}

}  // namespace
}  // namespace holo::calib
