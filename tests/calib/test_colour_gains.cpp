// Colour matching from the board's squares: four simulated cameras with different white balance
// and exposure see the same board; after their fitted gains a grey surface (and a coloured one)
// reads the same linear colour in all four within 2%. The gains travel in the camera's
// calibration file; older files without them still load.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <opencv2/core.hpp>

#include "board_poses.hpp"
#include "holo/calib/calibration_io.hpp"
#include "holo/calib/colour_gains.hpp"
#include "holo/calib/synthetic_board.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "shared_data.hpp"

namespace holo::calib {
namespace {

namespace fs = std::filesystem;

// A camera's 8-bit sRGB reading of linear radiance `radiance` (RGB) through its per-channel
// response `response`.
cv::Vec3b cameraReading(vec3 radiance, vec3 response) {
  cv::Vec3b bgr;
  for (int c = 0; c < 3; ++c)
    bgr[2 - c] = static_cast<std::uint8_t>(std::lround(255.0f * linearToSrgb(radiance[c] * response[c])));
  return bgr;
}

// The mean linear colour of a uniform surface over 2000 pixels of a camera with sensor noise
// (1.5 levels before 8-bit rounding), as the foreground pyramids average a visitor's pixels.
vec3 surfaceSeenBy(vec3 radiance, vec3 response, std::uint64_t seed) {
  cv::RNG rng(seed);
  glm::dvec3 sum(0.0);
  for (int k = 0; k < 2000; ++k) {
    vec3 pixel;
    for (int c = 0; c < 3; ++c) {
      const double code = 255.0 * linearToSrgb(radiance[c] * response[c]) + rng.gaussian(1.5);
      pixel[c] = srgbToLinear(static_cast<float>(std::clamp(std::round(code), 0.0, 255.0)) / 255.0f);
    }
    sum += glm::dvec3(pixel);
  }
  return vec3(sum / 2000.0);
}

// The board under the hall's light as a camera with `response` sees it: paper white reflects
// 90%, the print 4%, the light gives 0.6.
cv::Mat boardSeenBy(const BoardSpec& board, vec3 response, std::uint64_t seed) {
  Intrinsics K;
  K.width = 640;
  K.height = 480;
  K.fx = K.fy = 560.0f;
  K.cx = 319.5f;
  K.cy = 239.5f;
  K.distortion = {-0.12f, 0.03f, 0.0f, 0.0f, 0.0f};
  SyntheticViewOptions options;
  options.noise_sigma = 1.5f;
  options.seed = seed;
  const cv::Mat grey = renderBoardView(renderBoardTexture(board, 60), K,
                                       test::boardPose(board, 20, -15, 4, {0.01, -0.02, 0.45}), options);
  cv::Mat bgr(grey.size(), CV_8UC3);
  for (int y = 0; y < grey.rows; ++y)
    for (int x = 0; x < grey.cols; ++x) {
      const float paper = 0.04f + 0.86f * srgbToLinear(grey.at<std::uint8_t>(y, x) / 255.0f);
      bgr.at<cv::Vec3b>(y, x) = cameraReading(vec3(0.6f * paper), response);
    }
  return bgr;
}

float worstSpread(const std::vector<vec3>& colours) {
  float worst = 0.0f;
  for (int c = 0; c < 3; ++c) {
    float lo = colours[0][c], hi = colours[0][c];
    for (const vec3& v : colours) {
      lo = std::min(lo, v[c]);
      hi = std::max(hi, v[c]);
    }
    worst = std::max(worst, hi / lo - 1.0f);
  }
  return worst;
}

TEST(ColourGains, GreySurfaceReadsTheSameInFourCamerasWithin2Percent) {
  // White balance and exposure of four cameras: up to 40% apart per channel.
  const std::vector<vec3> responses = {
      {1.0f, 1.0f, 1.0f}, {1.3f, 1.1f, 0.8f}, {0.7f, 0.9f, 1.2f}, {1.1f, 0.75f, 1.0f}};
  for (const char* text : {"chessboard:9x6:0.03", "charuco:7x5:0.05:0.03:DICT_5X5_100"}) {
    const BoardSpec board = BoardSpec::parse(text);
    std::vector<BoardSquareLevels> levels;
    for (std::size_t i = 0; i < responses.size(); ++i) {
      const cv::Mat picture = boardSeenBy(board, responses[i], 10 + i);
      const BoardDetection detection = detectBoard(board, picture);
      ASSERT_TRUE(detection.usable()) << text << " camera " << i;
      levels.push_back(measureBoardSquares(board, picture, detection, "camera " + std::to_string(i)));
      // Every inner square: 20 of each colour on the 9x6 chessboard, 7 and 8 on the 7x5 ChArUco.
      const int squares = board.kind == BoardSpec::Kind::Chessboard ? 20 : 7;
      EXPECT_GE(levels.back().white_squares, squares) << text;
      EXPECT_GE(levels.back().black_squares, squares) << text;
    }
    const std::vector<vec3> gains = matchCameraColours(levels);
    ASSERT_EQ(gains.size(), responses.size());
    for (const vec3 surface : {vec3(0.3f), vec3(0.35f, 0.2f, 0.1f), vec3(0.18f), vec3(0.08f)}) {
      std::vector<vec3> raw, corrected;
      for (std::size_t i = 0; i < responses.size(); ++i) {
        const vec3 seen = surfaceSeenBy(surface, responses[i], 70 + i);
        raw.push_back(seen);
        corrected.push_back(seen * gains[i]);
      }
      EXPECT_GT(worstSpread(raw), 0.5f) << text;  // the cameras disagree by up to 70% uncorrected
      std::cout << text << " surface " << surface.r << " " << surface.g << " " << surface.b << ": spread "
                << 100.0f * worstSpread(raw) << "% raw, " << 100.0f * worstSpread(corrected) << "% matched\n";
      EXPECT_LT(worstSpread(corrected), 0.02f)
          << text << " surface " << surface.r << " " << surface.g << " " << surface.b;
    }
  }
}

TEST(ColourGains, ClippedWhiteAndAHiddenBoardAreRefusedWithAHint) {
  const BoardSpec board = BoardSpec::parse("chessboard:9x6:0.03");
  const cv::Mat bright = boardSeenBy(board, vec3(2.5f), 3);
  const BoardDetection detection = detectBoard(board, bright);
  ASSERT_TRUE(detection.usable());
  try {
    (void)measureBoardSquares(board, bright, detection, "camera 2");
    FAIL() << "clipped white squares accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("camera 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("lower the camera's exposure"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)measureBoardSquares(board, bright, BoardDetection{}, "camera 2"), InputError);
}

TEST(ColourGains, TravelInTheCalibrationFileAndOlderFilesLoadWithoutThem) {
  const fs::path dir = holo::test::scratchDir("calib_colour_gains");
  CameraCalibration in;
  in.serial = "CG-1";
  in.intrinsics = Intrinsics::fromFov(640, 480, 1.2f, 0.95f);
  in.colour_gains = {1.25f, 0.95f, 0.8f};
  const fs::path path = cameraCalibrationPath(dir, in.serial);
  saveCameraCalibration(path, in);
  const CameraCalibration out = loadCameraCalibration(path);
  EXPECT_FLOAT_EQ(out.colour_gains.r, 1.25f);
  EXPECT_FLOAT_EQ(out.colour_gains.g, 0.95f);
  EXPECT_FLOAT_EQ(out.colour_gains.b, 0.8f);

  // A file written before colour matching existed: every key but colour_gains.
  const fs::path old = dir / "camera_OLD-1.yml";
  {
    cv::FileStorage fs(old.string(), cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
    fs << "image_width" << 640 << "image_height" << 480 << "camera_name"
       << "OLD-1";
    fs << "camera_matrix" << cv::Mat(cv::Matx33d(500, 0, 320, 0, 500, 240, 0, 0, 1));
    fs << "distortion_model"
       << "plumb_bob"
       << "distortion_coefficients" << cv::Mat(1, 5, CV_64F, cv::Scalar(0));
    fs << "T_world_camera" << cv::Mat(cv::Matx44d::eye()) << "depth_scale" << 0.001;
    fs << "date"
       << "2026-01-01T00:00:00Z"
       << "rms" << 0.2;
  }
  EXPECT_EQ(loadCameraCalibration(old).colour_gains, vec3(1.0f));

  // A gain outside [0.1, 10] is refused, naming the field.
  in.colour_gains.g = 40.0f;
  try {
    saveCameraCalibration(path, in);
    FAIL() << "a gain of 40 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("colour_gains"), std::string::npos) << e.what();
  }
  EXPECT_FLOAT_EQ(loadCameraCalibration(path).colour_gains.g, 0.95f);  // the saved file stays
}

}  // namespace
}  // namespace holo::calib
