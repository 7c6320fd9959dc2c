// Camera poses in the pyramid frame from synthetic ChArUco photos with noise, against the truth.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "holo/calib/extrinsics.hpp"
#include "holo/calib/pose.hpp"
#include "holo/calib/synthetic_board.hpp"
#include "holo/core/error.hpp"
#include "museum_rig.hpp"
#include "shared_data.hpp"

namespace holo::calib {
namespace {

BoardDetection photograph(const BoardSpec& board, const BoardTexture& texture,
                          const cv::Matx44d& T_world_camera, const cv::Matx44d& T_world_board,
                          std::uint64_t seed, cv::Mat* image_out = nullptr) {
  SyntheticViewOptions options;
  options.noise_sigma = 2.0f;
  options.blur_sigma = 0.5f;
  options.seed = seed;
  const cv::Mat image =
      renderBoardView(texture, test::rigIntrinsics(), rigidInverse(T_world_camera) * T_world_board, options);
  if (image_out) *image_out = image;
  return detectBoard(board, image);
}

// The bar: with noise on, every camera's T_world_camera within 3 mm and 0.3 degrees.
TEST(Extrinsics, FourCamerasFromBoardsAtKnownPlacements) {
  const BoardSpec board = BoardSpec::parse("charuco:7x5:0.08:0.06:DICT_5X5_100");
  const BoardTexture texture = renderBoardTexture(board, 60);
  ExtrinsicsProblem problem;
  std::vector<cv::Matx44d> truth;
  for (int f = 0; f < 4; ++f) {
    truth.push_back(test::rigCamera(f));
    problem.cameras.push_back(test::rigIntrinsics());
    problem.placements.push_back({test::rigBoardPlacement(board, f), true});
    cv::Mat image;
    problem.observations.push_back(
        {f, f,
         photograph(board, texture, truth.back(), problem.placements.back().T_world_board, 10 + f, &image)});
    cv::imwrite((holo::test::scratchDir("calib_extrinsics_" + std::to_string(f)) / "view.png").string(),
                image);
    ASSERT_GE(problem.observations.back().detection.image_points.size(), 20u) << "camera " << f;
  }
  const ExtrinsicsResult result = calibrateExtrinsics(problem);
  for (int f = 0; f < 4; ++f) {
    const double dt = translationError(result.T_world_camera[f], truth[f]);
    const double dr = rotationErrorDeg(result.T_world_camera[f], truth[f]);
    std::cout << "camera " << f << ": " << dt * 1000 << " mm, " << dr << " deg, RMS " << result.camera_rms[f]
              << " px over " << result.camera_corners[f] << " corners\n";
    EXPECT_LT(dt, 0.003) << "camera " << f;
    EXPECT_LT(dr, 0.3) << "camera " << f;
    EXPECT_LT(result.camera_rms[f], 0.5);
  }
}

// A board two cameras see at once, at a placement nobody measured: the joint adjustment
// recovers it and keeps both cameras within the bars.
TEST(Extrinsics, BoardSeenByTwoCamerasAtOnceIsRecovered) {
  const BoardSpec board = BoardSpec::parse("charuco:7x5:0.12:0.09:DICT_5X5_100");
  const BoardTexture texture = renderBoardTexture(board, 60);
  ExtrinsicsProblem problem;
  std::vector<cv::Matx44d> truth;
  for (int f = 0; f < 2; ++f) {
    truth.push_back(test::rigCamera(f));
    problem.cameras.push_back(test::rigIntrinsics());
    problem.placements.push_back({test::rigBoardPlacement(board, f), true});
    problem.observations.push_back(
        {f, f, photograph(board, texture, truth.back(), problem.placements.back().T_world_board, 20 + f)});
  }
  // Standing between faces 0 and 1 (azimuth 45 degrees), facing the corner of the base.
  const vec3 d = glm::normalize(vec3(1.0f, 0.0f, 1.0f));
  const cv::Vec3d z(d.x, 0, d.z), y(0, 1, 0), x = y.cross(z);
  const cv::Vec3d centre = 1.5 * z + cv::Vec3d(0, -0.1, 0);
  const cv::Rect2d e = board.extent();
  const cv::Matx33d R(x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2]);
  const cv::Vec3d t = centre - R * cv::Vec3d(e.x + e.width / 2, e.y + e.height / 2, 0);
  const cv::Matx44d shared_truth(R(0, 0), R(0, 1), R(0, 2), t[0], R(1, 0), R(1, 1), R(1, 2), t[1], R(2, 0),
                                 R(2, 1), R(2, 2), t[2], 0, 0, 0, 1);
  problem.placements.push_back({cv::Matx44d::eye(), false});
  for (int f = 0; f < 2; ++f) {
    problem.observations.push_back({f, 2, photograph(board, texture, truth[f], shared_truth, 30 + f)});
    ASSERT_GE(problem.observations.back().detection.image_points.size(), 6u)
        << "camera " << f << " sees the shared board";
  }
  const ExtrinsicsResult result = calibrateExtrinsics(problem);
  EXPECT_GT(result.iterations, 0);
  const double board_dt = translationError(result.T_world_board[2], shared_truth);
  const double board_dr = rotationErrorDeg(result.T_world_board[2], shared_truth);
  std::cout << "shared board: " << board_dt * 1000 << " mm, " << board_dr << " deg; RMS " << result.rms
            << " px\n";
  EXPECT_LT(board_dt, 0.01);
  EXPECT_LT(board_dr, 0.5);
  for (int f = 0; f < 2; ++f) {
    EXPECT_LT(translationError(result.T_world_camera[f], truth[f]), 0.003) << "camera " << f;
    EXPECT_LT(rotationErrorDeg(result.T_world_camera[f], truth[f]), 0.3) << "camera " << f;
  }
}

TEST(Extrinsics, CameraWithoutAKnownBoardIsAnInputError) {
  ExtrinsicsProblem problem;
  problem.cameras = {test::rigIntrinsics(), test::rigIntrinsics()};
  problem.placements = {{cv::Matx44d::eye(), true}};
  BoardDetection few;
  few.image_points = {{1, 1}, {2, 2}};
  few.object_points = {{0, 0, 0}, {1, 0, 0}};
  problem.observations = {{1, 0, few}};
  try {
    (void)calibrateExtrinsics(problem, "pyramid.yml");
    FAIL() << "calibrated without views";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "camera 0");
    EXPECT_EQ(e.file(), "pyramid.yml");
  }
  problem.observations = {{5, 0, few}};
  EXPECT_THROW(calibrateExtrinsics(problem), InputError);
}

}  // namespace
}  // namespace holo::calib
