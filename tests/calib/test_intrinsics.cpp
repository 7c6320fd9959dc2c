// Board specs, board detection and intrinsics: on OpenCV's real chessboard photos against
// OpenCV's own reference, and on synthetic photos rendered with a known camera.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "board_poses.hpp"
#include "holo/calib/board.hpp"
#include "holo/calib/intrinsics.hpp"
#include "holo/calib/synthetic_board.hpp"
#include "holo/core/error.hpp"
#include "shared_data.hpp"

namespace holo::calib {
namespace {

namespace fs = std::filesystem;

TEST(BoardSpec, ParsesBothKinds) {
  const BoardSpec chess = BoardSpec::parse("chessboard:9x6:0.025");
  EXPECT_EQ(chess.kind, BoardSpec::Kind::Chessboard);
  EXPECT_EQ(chess.cols, 9);
  EXPECT_EQ(chess.rows, 6);
  EXPECT_DOUBLE_EQ(chess.square_m, 0.025);
  EXPECT_EQ(chess.allCorners().size(), 54u);
  const BoardSpec charuco = BoardSpec::parse("charuco:7x5:0.04:0.03:5x5_100");
  EXPECT_EQ(charuco.kind, BoardSpec::Kind::Charuco);
  EXPECT_EQ(charuco.dictionary, "DICT_5X5_100");
  EXPECT_EQ(charuco.allCorners().size(), 24u);  // (7-1) x (5-1) inner corners
}

TEST(BoardSpec, BadSpecsNameTheirField) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"chessboard:9x6", "board"},
      {"circles:9x6:0.02", "board"},
      {"chessboard:9by6:0.025", "board size"},
      {"chessboard:1x6:0.025", "board size"},
      {"chessboard:9x6:-1", "square size"},
      {"chessboard:9x6:nan", "square size"},
      {"charuco:7x5:0.04:0.05:DICT_5X5_100", "marker size"},
      {"charuco:7x5:0.04:0.03:DICT_9X9_1", "dictionary"},
      {"charuco:30x30:0.04:0.03:DICT_4X4_50", "dictionary"},  // needs 450 markers
  };
  for (const auto& [text, field] : cases) {
    try {
      (void)BoardSpec::parse(text);
      ADD_FAILURE() << text << " parsed";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << text << ": " << e.what();
      EXPECT_EQ(e.file(), "--board");
    }
  }
}

// The synthetic photos must put every corner where the camera model projects it: every
// synthetic accuracy figure rests on this. A sharp, noiseless, tilted view of each board kind,
// with and without lens distortion, detected by OpenCV, against the projected truth.
TEST(SyntheticBoard, CornersLandWhereTheCameraProjectsThem) {
  for (const char* text : {"chessboard:9x6:0.025", "charuco:7x5:0.04:0.03:DICT_5X5_100"}) {
    for (const bool distorted : {false, true}) {
      const BoardSpec board = BoardSpec::parse(text);
      Intrinsics K;
      K.width = 640;
      K.height = 480;
      K.fx = K.fy = 600.0f;
      K.cx = 319.5f;
      K.cy = 239.5f;
      if (distorted) K.distortion = {-0.15f, 0.04f, 0.001f, -0.001f, 0.0f};
      const cv::Matx44d pose = test::boardPose(board, 15, -10, 5, {0.0, 0.0, 0.5});
      SyntheticViewOptions options;
      options.noise_sigma = 0;
      options.supersample = 4;
      const cv::Mat image = renderBoardView(renderBoardTexture(board, 60), K, pose, options);
      const BoardDetection found = detectBoard(board, image);
      ASSERT_EQ(found.image_points.size(), board.allCorners().size()) << text;
      const CameraModel camera(K, mat4(1.0f));
      double sum = 0;
      for (std::size_t i = 0; i < found.image_points.size(); ++i) {
        const cv::Point3f& p = found.object_points[i];
        const cv::Vec4d q = pose * cv::Vec4d(p.x, p.y, p.z, 1.0);
        const auto pixel = camera.projectCamera(vec3(q[0], q[1], q[2]));
        ASSERT_TRUE(pixel);
        sum += cv::norm(cv::Point2d(pixel->x, pixel->y) - cv::Point2d(found.image_points[i]));
      }
      const double mean = sum / static_cast<double>(found.image_points.size());
      EXPECT_LT(mean, 0.1) << text << (distorted ? " distorted" : " pinhole");
    }
  }
}

TEST(BoardDetection, BlankAndEmptyImagesFindNothing) {
  const BoardSpec board = BoardSpec::parse("charuco:7x5:0.04:0.03:DICT_5X5_100");
  EXPECT_TRUE(detectBoard(board, cv::Mat()).image_points.empty());
  EXPECT_TRUE(detectBoard(board, cv::Mat(480, 640, CV_8UC3, cv::Scalar(90, 90, 90))).image_points.empty());
  EXPECT_TRUE(
      detectBoard(BoardSpec::parse("chessboard:9x6:0.025"), cv::Mat(480, 640, CV_8UC1, cv::Scalar(255)))
          .image_points.empty());
}

// The bar: on OpenCV's real left-camera photos, fx and fy within 1% of OpenCV's own
// calibration (left_intrinsics.yml) and RMS below 0.5 px.
TEST(Intrinsics, RealChessboardPhotosMatchOpenCvReference) {
  HOLO_REQUIRE_SHARED_DATA("calib/chessboard_9x6/left_intrinsics.yml");
  const fs::path dir = holo::test::sharedData("calib/chessboard_9x6");
  const BoardSpec board = BoardSpec::parse("chessboard:9x6:0.025");
  std::vector<BoardView> views;
  cv::Size size;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().rfind("left", 0) == 0 && entry.path().extension() == ".jpg")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 10u);
  for (const fs::path& file : files) {
    const cv::Mat image = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty()) << file;
    size = image.size();
    views.push_back({file.filename().string(), detectBoard(board, image)});
  }
  const IntrinsicsResult result = calibrateIntrinsics(board, views, size);

  cv::FileStorage reference((dir / "left_intrinsics.yml").string(), cv::FileStorage::READ);
  cv::Mat K;
  reference["camera_matrix"] >> K;
  const double fx_ref = K.at<double>(0, 0), fy_ref = K.at<double>(1, 1);
  std::cout << "real left camera: fx " << result.intrinsics.fx << " (ref " << fx_ref << "), fy "
            << result.intrinsics.fy << " (ref " << fy_ref << "), cx " << result.intrinsics.cx << ", cy "
            << result.intrinsics.cy << ", RMS " << result.rms << " px over " << result.used_views.size()
            << " views\n";
  EXPECT_GE(result.used_views.size(), 12u);
  EXPECT_NEAR(result.intrinsics.fx, fx_ref, 0.01 * fx_ref);
  EXPECT_NEAR(result.intrinsics.fy, fy_ref, 0.01 * fy_ref);
  EXPECT_LT(result.rms, 0.5);
}

Intrinsics syntheticCamera() {
  Intrinsics K;
  K.width = 640;
  K.height = 480;
  K.fx = 600.0f;
  K.fy = 604.0f;
  K.cx = 322.0f;
  K.cy = 236.0f;
  K.distortion = {-0.12f, 0.03f, 0.0f, 0.0f, 0.0f};
  return K;
}

std::vector<BoardView> syntheticViews(const BoardSpec& board, const Intrinsics& K, float blur = 0.0f) {
  const BoardTexture texture = renderBoardTexture(board, 60);
  std::vector<BoardView> views;
  const double tilts[][3] = {{0, 0, 0},   {25, 0, 5},    {-25, 0, -5},   {0, 25, 10},   {0, -25, -10},
                             {20, 20, 0}, {-20, 20, 15}, {20, -20, -15}, {-20, -20, 0}, {10, -30, 30}};
  const cv::Vec3d centres[] = {
      {0, 0, 0.45},      {0.04, 0.03, 0.5}, {-0.04, -0.03, 0.5}, {0.05, -0.04, 0.55}, {-0.05, 0.04, 0.5},
      {0.0, 0.05, 0.55}, {0.06, 0.0, 0.5},  {-0.06, 0.0, 0.5},   {0.0, -0.05, 0.5},   {0.03, 0.03, 0.45}};
  for (int i = 0; i < 10; ++i) {
    SyntheticViewOptions options;
    options.seed = static_cast<std::uint64_t>(100 + i);
    options.blur_sigma = blur;
    const cv::Matx44d pose = test::boardPose(board, tilts[i][0], tilts[i][1], tilts[i][2], centres[i]);
    const cv::Mat image = renderBoardView(texture, K, pose, options);
    views.push_back({"synthetic" + std::to_string(i), detectBoard(board, image)});
  }
  return views;
}

TEST(Intrinsics, SyntheticChessboardRecoversTheCamera) {
  const BoardSpec board = BoardSpec::parse("chessboard:9x6:0.025");
  const Intrinsics truth = syntheticCamera();
  const IntrinsicsResult result = calibrateIntrinsics(board, syntheticViews(board, truth), {640, 480});
  std::cout << "synthetic chessboard: fx " << result.intrinsics.fx << " fy " << result.intrinsics.fy << " cx "
            << result.intrinsics.cx << " cy " << result.intrinsics.cy << " k1 "
            << result.intrinsics.distortion[0] << " RMS " << result.rms << "\n";
  EXPECT_EQ(result.used_views.size(), 10u);
  EXPECT_NEAR(result.intrinsics.fx, truth.fx, 0.005 * truth.fx);
  EXPECT_NEAR(result.intrinsics.fy, truth.fy, 0.005 * truth.fy);
  EXPECT_NEAR(result.intrinsics.cx, truth.cx, 3.0);
  EXPECT_NEAR(result.intrinsics.cy, truth.cy, 3.0);
  EXPECT_NEAR(result.intrinsics.distortion[0], truth.distortion[0], 0.03);
  EXPECT_LT(result.rms, 0.3);
}

TEST(Intrinsics, SyntheticCharucoRecoversTheCamera) {
  const BoardSpec board = BoardSpec::parse("charuco:7x5:0.03:0.022:DICT_5X5_100");
  const Intrinsics truth = syntheticCamera();
  const IntrinsicsResult result = calibrateIntrinsics(board, syntheticViews(board, truth), {640, 480});
  std::cout << "synthetic ChArUco: fx " << result.intrinsics.fx << " fy " << result.intrinsics.fy << " RMS "
            << result.rms << " views " << result.used_views.size() << "\n";
  EXPECT_GE(result.used_views.size(), 8u);
  EXPECT_NEAR(result.intrinsics.fx, truth.fx, 0.005 * truth.fx);
  EXPECT_NEAR(result.intrinsics.fy, truth.fy, 0.005 * truth.fy);
  EXPECT_LT(result.rms, 0.5);
}

TEST(Intrinsics, TooFewViewsIsAnInputError) {
  const BoardSpec board = BoardSpec::parse("chessboard:9x6:0.025");
  std::vector<BoardView> views = {{"a", {}}, {"b", {}}, {"c", {}}, {"d", {}}};
  try {
    (void)calibrateIntrinsics(board, views, {640, 480}, "photos/*.jpg");
    FAIL() << "calibrated without views";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "photos/*.jpg");
    EXPECT_NE(std::string(e.what()).find("0 of 4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace holo::calib
