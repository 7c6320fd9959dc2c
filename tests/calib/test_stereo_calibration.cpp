// A stereo pair from two photo sets (calib::calibrateStereoPhotos, `holopyramid calibrate stereo`):
// OpenCV's real stereo photos against OpenCV's own reference, the written file read back by stock
// OpenCV, and the refusals of bad input.
#include <gtest/gtest.h>

#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "holo/calib/stereo_calibration.hpp"
#include "holo/core/error.hpp"
#include "shared_data.hpp"

namespace holo::calib {
namespace {

namespace fs = std::filesystem;

const BoardSpec& chessboard() {
  static const BoardSpec board = BoardSpec::parse("chessboard:9x6:0.025");
  return board;
}

// The InputError's message, or a failure when none was thrown.
template <typename F>
std::string inputError(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

// ../shared/data/calib/chessboard_9x6: left within 1 % of left_intrinsics.yml (OpenCV's
// calibration of the left camera); the pairs are those stereo_calib.xml lists (it holds no pose, so
// the pose is held against cv::stereoCalibrate on the same corners, a separate estimator); the loop
// closure and the rectification.
TEST(StereoCalibration, RealPhotosAgainstOpenCVsReference) {
  HOLO_REQUIRE_SHARED_DATA("calib/chessboard_9x6/stereo_calib.xml");
  const fs::path dir = holo::test::sharedData("calib/chessboard_9x6");
  std::ostringstream log;
  const StereoCalibration s = calibrateStereoPhotos((dir / "left[0-9]*.jpg").string(),
                                                    (dir / "right[0-9]*.jpg").string(), chessboard(), log);
  std::cout << log.str();

  cv::FileStorage list((dir / "stereo_calib.xml").string(), cv::FileStorage::READ);
  std::vector<std::string> names;
  list["imagelist"] >> names;
  ASSERT_EQ(names.size(), 2 * s.left_files.size());
  for (std::size_t k = 0; k < s.left_files.size(); ++k) {
    EXPECT_EQ(fs::path(s.left_files[k]).filename().string(), names[2 * k]);
    EXPECT_EQ(fs::path(s.right_files[k]).filename().string(), names[2 * k + 1]);
  }
  EXPECT_TRUE(list["R"].empty() && list["T"].empty()) << "stereo_calib.xml now holds a pose: compare with it";

  cv::FileStorage reference((dir / "left_intrinsics.yml").string(), cv::FileStorage::READ);
  cv::Matx33d K;
  reference["camera_matrix"] >> K;
  const Intrinsics& left = s.left.intrinsics;
  std::cout << "left fx " << left.fx << " fy " << left.fy << " cx " << left.cx << " cy " << left.cy
            << " (reference " << K(0, 0) << " " << K(1, 1) << " " << K(0, 2) << " " << K(1, 2) << ")\n";
  EXPECT_NEAR(left.fx, K(0, 0), 0.01 * K(0, 0));
  EXPECT_NEAR(left.fy, K(1, 1), 0.01 * K(1, 1));
  EXPECT_NEAR(left.cx, K(0, 2), 0.01 * K(0, 2));
  EXPECT_NEAR(left.cy, K(1, 2), 0.01 * K(1, 2));
  for (const StepVerdict& verdict : s.verdicts) EXPECT_TRUE(verdict.pass) << formatVerdict(verdict);

  std::cout << "pairs " << s.pose.pairs << ", baseline " << s.baseline_mm << " mm, rotation "
            << s.rotation_deg << " deg, rms " << s.pose.rms_px << " px; loop closure median "
            << s.loop_median_mm << " mm / " << s.loop_median_deg << " deg, worst " << s.loop_worst_mm
            << " mm / " << s.loop_worst_deg << " deg; cv::stereoCalibrate rms " << s.opencv_rms_px << " px, "
            << s.opencv_difference_mm << " mm / " << s.opencv_difference_deg
            << " deg apart; rectified rows median " << s.rectified_row_median_px << " px, worst "
            << s.rectified_row_worst_px << " px\n";
  EXPECT_EQ(s.pose.pairs, 13);
  EXPECT_LT(s.pose.rms_px, 0.5);
  // A side-by-side pair about 3.3 squares apart, its right camera along the left one's x axis.
  EXPECT_GT(s.baseline_mm, 75.0);
  EXPECT_LT(s.baseline_mm, 90.0);
  EXPECT_GT(std::abs(s.T[0]), 0.95 * cv::norm(s.T));
  EXPECT_LT(s.rotation_deg, 2.0);
  EXPECT_LT(s.opencv_difference_mm, 1.0);
  EXPECT_LT(s.opencv_difference_deg, 0.1);
  EXPECT_LT(s.loop_median_mm, 2.0);
  EXPECT_LT(s.loop_median_deg, 0.5);
  EXPECT_LT(s.loop_worst_mm, 5.0);
  EXPECT_LT(s.loop_worst_deg, 1.0);
  EXPECT_LT(s.rectified_row_median_px, 0.3);
  EXPECT_LT(s.rectified_row_worst_px, 1.5);
  EXPECT_EQ(s.picture.size(), cv::Size(1280, 480));

  const fs::path out = holo::test::scratchDir("calib_stereo") / "stereo.yml";
  saveStereoCalibration(out, s);
  cv::FileStorage saved(out.string(), cv::FileStorage::READ);
  ASSERT_TRUE(saved.isOpened());
  cv::Mat R, T, K1;
  saved["R"] >> R;
  saved["T"] >> T;
  saved["left_camera_matrix"] >> K1;
  ASSERT_EQ(R.size(), cv::Size(3, 3));
  ASSERT_EQ(T.size(), cv::Size(1, 3));
  EXPECT_NEAR(1000.0 * cv::norm(T), static_cast<double>(saved["baseline_mm"]), 1e-9);
  EXPECT_LT(cv::norm(cv::Mat(R * R.t() - cv::Mat::eye(3, 3, CV_64F))), 1e-9);
  EXPECT_NEAR(K1.at<double>(0, 0), left.fx, 1e-3);
  EXPECT_EQ(static_cast<int>(saved["pairs"]), 13);
}

TEST(StereoCalibration, BadInputIsNamed) {
  HOLO_REQUIRE_SHARED_DATA("calib/chessboard_9x6/left01.jpg");
  const fs::path data = holo::test::sharedData("calib/chessboard_9x6");
  const fs::path dir = holo::test::scratchDir("calib_stereo_bad");
  const std::string left = (data / "left[0-9]*.jpg").string();
  std::ostringstream log;

  // A set that is not there.
  std::string message = inputError(
      [&] { calibrateStereoPhotos(left, (dir / "missing" / "right*.jpg").string(), chessboard(), log); });
  EXPECT_NE(message.find("missing/right*.jpg"), std::string::npos) << message;
  EXPECT_NE(message.find("no match"), std::string::npos) << message;

  // One photo fewer on the right: the pairs cannot be matched.
  fs::create_directories(dir / "short");
  for (int k : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13})
    fs::copy_file(data / ("right" + std::string(k < 10 ? "0" : "") + std::to_string(k) + ".jpg"),
                  dir / "short" / ("right" + std::to_string(100 + k) + ".jpg"));
  message = inputError(
      [&] { calibrateStereoPhotos(left, (dir / "short" / "right*.jpg").string(), chessboard(), log); });
  EXPECT_NE(message.find("short/right*.jpg"), std::string::npos) << message;
  EXPECT_NE(message.find("13 photos"), std::string::npos) << message;
  EXPECT_NE(message.find("12"), std::string::npos) << message;

  // Photos without the board.
  fs::create_directories(dir / "blank");
  for (int k = 0; k < 9; ++k)
    for (const char* side : {"left", "right"})
      cv::imwrite((dir / "blank" / (std::string(side) + std::to_string(k) + ".png")).string(),
                  cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(128 + 10 * k)));
  message = inputError([&] {
    calibrateStereoPhotos((dir / "blank" / "left*.png").string(), (dir / "blank" / "right*.png").string(),
                          chessboard(), log);
  });
  EXPECT_NE(message.find("blank/left*.png"), std::string::npos) << message;
  EXPECT_NE(message.find("board"), std::string::npos) << message;
  EXPECT_NE(message.find("found in 0 of 9"), std::string::npos) << message;
}

}  // namespace
}  // namespace holo::calib
