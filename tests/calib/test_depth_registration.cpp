// Depth-to-colour registration of a two-device camera on simulated views: a colour camera and a
// depth sensor 5 cm beside it, turned by about a degree, whose depth reads 2% short. From eight
// views of the board the registration recovers the depth sensor's pose within 3 mm / 0.3 degrees
// and its scale within 0.3%; depth reprojected into the colour image with it lands on the
// board's true depth, and without it measurably does not.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <opencv2/calib3d.hpp>

#include "board_poses.hpp"
#include "holo/calib/depth_registration.hpp"
#include "holo/calib/synthetic_board.hpp"
#include "holo/capture/depth_to_colour.hpp"
#include "holo/core/error.hpp"

namespace holo::calib {
namespace {

constexpr double kTrueScale = 1.02;  // true depth / what the sensor reports

Intrinsics colourIntrinsics() {
  Intrinsics K;
  K.width = 640;
  K.height = 480;
  K.fx = K.fy = 560.0f;
  K.cx = 319.5f;
  K.cy = 239.5f;
  K.distortion = {-0.08f, 0.02f, 0.0f, 0.0f, 0.0f};
  return K;
}

Intrinsics depthIntrinsics() {
  Intrinsics K;
  K.width = 320;
  K.height = 240;
  K.fx = K.fy = 290.0f;
  K.cx = 160.5f;
  K.cy = 118.5f;
  return K;
}

cv::Matx44d trueColourFromDepth() {
  cv::Matx33d R;
  cv::Rodrigues(cv::Vec3d(0.01, -0.02, 0.015), R);
  return {R(0, 0), R(0, 1), R(0, 2), 0.052, R(1, 0), R(1, 1), R(1, 2), -0.004,
          R(2, 0), R(2, 1), R(2, 2), 0.008, 0,       0,       0,       1};
}

// Ray from the origin along `ray` onto the board (pose T_camera_board): the hit's z, or
// `wall` where the ray misses the board's printed extent.
double boardDepthAlong(const BoardSpec& board, const cv::Matx44d& T_camera_board, const cv::Vec3d& ray,
                       double wall) {
  const cv::Vec3d n(T_camera_board(0, 2), T_camera_board(1, 2), T_camera_board(2, 2));
  const cv::Vec3d o(T_camera_board(0, 3), T_camera_board(1, 3), T_camera_board(2, 3));
  const double t = n.dot(o) / n.dot(ray);
  const cv::Vec3d p = t * ray;
  const cv::Matx44d inv = T_camera_board.inv();
  const cv::Vec4d q = inv * cv::Vec4d(p[0], p[1], p[2], 1.0);
  const cv::Rect2d e = board.extent();
  if (t <= 0 || q[0] < e.x || q[0] > e.x + e.width || q[1] < e.y || q[1] > e.y + e.height) return wall;
  return p[2];
}

// What the depth sensor reports: true depth / 1.02, noise growing with distance, millimetres.
cv::Mat depthView(const BoardSpec& board, const cv::Matx44d& T_colour_board, std::uint64_t seed) {
  const Intrinsics K = depthIntrinsics();
  const cv::Matx44d T_depth_board = trueColourFromDepth().inv() * T_colour_board;
  cv::RNG rng(seed);
  cv::Mat depth(K.height, K.width, CV_32FC1);
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) {
      const cv::Vec3d ray((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);
      const double z = boardDepthAlong(board, T_depth_board, ray, 3.0);
      const double reported = z / kTrueScale + rng.gaussian(0.0015 * z * z);
      depth.at<float>(y, x) = static_cast<float>(std::round(reported * 1000.0) / 1000.0);
    }
  return depth;
}

struct View {
  cv::Matx44d T_colour_board;
  cv::Mat colour;
  cv::Mat depth;
};

std::vector<View> views(const BoardSpec& board) {
  const double poses[][6] = {{25, 0, 5, 0.0, 0.0, 0.8},      {-25, 10, -5, 0.05, 0.02, 1.0},
                             {0, 30, 0, -0.05, 0.0, 0.9},    {10, -30, 10, 0.0, -0.04, 1.2},
                             {-20, -20, 0, 0.06, 0.03, 0.7}, {20, 25, -8, -0.04, 0.02, 1.1},
                             {5, 5, 3, 0.0, 0.0, 1.3},       {-15, 15, 0, 0.02, -0.03, 0.75}};
  std::vector<View> out;
  const BoardTexture texture = renderBoardTexture(board, 60);
  std::uint64_t seed = 40;
  for (const auto& p : poses) {
    View v;
    v.T_colour_board = test::boardPose(board, p[0], p[1], p[2], {p[3], p[4], p[5]});
    SyntheticViewOptions options;
    options.seed = ++seed;
    v.colour = renderBoardView(texture, colourIntrinsics(), v.T_colour_board, options);
    v.depth = depthView(board, v.T_colour_board, seed);
    out.push_back(std::move(v));
  }
  return out;
}

mat4 toGlm(const cv::Matx44d& T) {
  mat4 out(1.0f);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[c][r] = static_cast<float>(T(r, c));
  return out;
}

TEST(DepthRegistration, RecoversTheDepthSensorsPoseAndScaleFromTheBoard) {
  const BoardSpec board = BoardSpec::parse("chessboard:9x6:0.04");
  const std::vector<View> seen = views(board);
  std::vector<PlanePair> pairs;
  for (const View& v : seen) {
    const BoardDetection detection = detectBoard(board, v.colour);
    ASSERT_TRUE(detection.usable());
    const std::optional<cv::Matx44d> pose = boardPoseInCamera(detection, colourIntrinsics());
    ASSERT_TRUE(pose);
    // No prior knowledge of the sensor's offset: the guess is the identity.
    const std::optional<DepthPlaneFit> fit =
        fitBoardPlaneInDepth(v.depth, depthIntrinsics(), board, *pose, cv::Matx44d::eye());
    ASSERT_TRUE(fit);
    EXPECT_GT(fit->inliers, 1000);
    EXPECT_LT(fit->rms_m, 0.004);
    pairs.push_back({*boardPlaneInCamera(detection, colourIntrinsics()), fit->plane});
  }
  const DepthRegistration registration = fitDepthRegistration(pairs, "camera 0");
  EXPECT_EQ(registration.views, 8);
  EXPECT_NEAR(registration.scale_factor / kTrueScale - 1.0, 0.0, 0.003);
  const cv::Matx44d truth = trueColourFromDepth();
  const cv::Vec3d dt(registration.T_colour_depth(0, 3) - truth(0, 3),
                     registration.T_colour_depth(1, 3) - truth(1, 3),
                     registration.T_colour_depth(2, 3) - truth(2, 3));
  EXPECT_LT(cv::norm(dt), 0.003);
  const cv::Matx33d dR = registration.T_colour_depth.get_minor<3, 3>(0, 0).t() * truth.get_minor<3, 3>(0, 0);
  cv::Vec3d rvec;
  cv::Rodrigues(dR, rvec);
  EXPECT_LT(cv::norm(rvec) * 180.0 / CV_PI, 0.3);
  EXPECT_LT(registration.rms_distance_mm, 3.0);
  std::cout << "scale " << registration.scale_factor << " (truth " << kTrueScale << "), translation error "
            << cv::norm(dt) * 1000.0 << " mm, rotation error " << cv::norm(rvec) * 180.0 / CV_PI << " deg\n";

  // Depth reprojected into the colour image with the registration (and the scale) lands on the
  // board's true depth; without registration (the depth image taken as the colour's, the
  // nominal scale) it is centimetres off.
  const View& v = seen[2];
  cv::Mat scaled;
  v.depth.convertTo(scaled, CV_32FC1, registration.scale_factor);
  const cv::Mat registered =
      capture::DepthToColour(depthIntrinsics(), colourIntrinsics(), toGlm(registration.T_colour_depth))
          .apply(scaled);
  const cv::Mat unregistered =
      capture::DepthToColour(depthIntrinsics(), colourIntrinsics(), mat4(1.0f)).apply(v.depth);
  const CameraModel colour(colourIntrinsics(), mat4(1.0f));
  std::vector<double> with, without;
  for (int y = 0; y < 480; y += 3)
    for (int x = 0; x < 640; x += 3) {
      const vec3 ray = colour.unprojectToPlane({static_cast<float>(x), static_cast<float>(y)});
      const double truth_z = boardDepthAlong(board, v.T_colour_board, cv::Vec3d(ray.x, ray.y, ray.z), -1.0);
      if (truth_z < 0) continue;
      const float a = registered.at<float>(y, x), b = unregistered.at<float>(y, x);
      if (a > 0) with.push_back(std::abs(a - truth_z));
      if (b > 0) without.push_back(std::abs(b - truth_z));
    }
  ASSERT_GT(with.size(), 2000u);
  auto median = [](std::vector<double> values) {
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2),
                     values.end());
    return values[values.size() / 2];
  };
  const double with_mm = 1000.0 * median(with), without_mm = 1000.0 * median(without);
  std::cout << "board depth error in the colour image: " << with_mm << " mm registered, " << without_mm
            << " mm unregistered\n";
  EXPECT_LT(with_mm, 3.0);
  EXPECT_GT(without_mm, 10.0);
  // Registered depth covers the board without holes from the 2x finer colour grid.
  EXPECT_GT(static_cast<double>(with.size()), 0.97 * static_cast<double>(without.size()));
}

TEST(DepthRegistration, TooFewOrAlikeViewsAreRefusedWithAHint) {
  const PlanePair same{{cv::Vec3d(0, 0, 1), 1.0}, {cv::Vec3d(0, 0, 1), 0.98}};
  EXPECT_THROW((void)fitDepthRegistration({same, same, same}, "camera 1"), InputError);
  try {
    (void)fitDepthRegistration({same, same, same, same, same}, "camera 1");
    FAIL() << "five views of the same plane accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("camera 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("tilt the board"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace holo::calib
