// The cameras filling each other's holes on a hand-built scene: two cameras 2 m apart look at a
// visitor (a square 2 m away) in front of the hall's wall; depth images are ray-cast exactly.
// A hole in B's reading of the visitor is filled from A's measurement; a visitor A sees but a
// wall hides from B is never painted into B (the adversary a fill without a visibility check
// loses to).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/depthfilter/cross_camera_fill.hpp"

namespace holo::depthfilter {
namespace {

constexpr int kWidth = 96, kHeight = 72;

// An axis-aligned rectangle in the plane z = const, facing the cameras (at z = 0).
struct Rectangle {
  float z, x_min, x_max, y_min, y_max;
};

const Rectangle kVisitor{2.0f, -0.3f, 0.3f, -0.4f, 0.4f};
const Rectangle kHallWall{5.0f, -10.0f, 10.0f, -10.0f, 10.0f};
// Between B and the visitor, off A's line of sight: hides the visitor from B only.
const Rectangle kWallBeforeB{1.0f, 0.15f, 0.85f, -0.5f, 0.5f};

CameraModel camera(float x) {
  const Intrinsics K = Intrinsics::fromFov(kWidth, kHeight, 1.2f, 0.95f);
  return CameraModel(K, lookAtCameraToWorld(vec3(x, 0.0f, 0.0f), vec3(0.0f, 0.0f, 2.0f)));
}

// Camera-frame depth of the nearest rectangle per pixel (0 where none), and which one it is.
cv::Mat castDepth(const CameraModel& cam, const std::vector<Rectangle>& scene,
                  cv::Mat* nearest_index = nullptr) {
  cv::Mat depth(kHeight, kWidth, CV_32FC1, cv::Scalar(0.0f));
  if (nearest_index) *nearest_index = cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(255));
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const Ray ray = cam.ray(vec2(float(x), float(y)));
      float best = std::numeric_limits<float>::infinity();
      for (std::size_t i = 0; i < scene.size(); ++i) {
        const Rectangle& r = scene[i];
        const float t = (r.z - ray.origin.z) / ray.direction.z;
        const vec3 p = ray.origin + t * ray.direction;
        if (!(t > 0.0f) || p.x < r.x_min || p.x > r.x_max || p.y < r.y_min || p.y > r.y_max || t >= best)
          continue;
        best = t;
        depth.at<float>(y, x) = transformPoint(cam.T_camera_world(), p).z;
        if (nearest_index) nearest_index->at<std::uint8_t>(y, x) = std::uint8_t(i);
      }
    }
  return depth;
}

struct TwoCameras {
  std::vector<CameraModel> cameras{camera(-1.0f), camera(1.0f)};  // A, B
  std::vector<CrossCameraView> views;
  std::vector<cv::Mat> out;
  std::vector<CrossCameraCounts> counts;
  static CrossCameraFillConfig on() {
    CrossCameraFillConfig c;
    c.enabled = true;
    return c;
  }

  // A sees `scene_a`, B `scene_b`; B's reading is dropped where `drop_b` is non-zero. Each mask
  // is where the visitor (scene index 0) is the nearest surface and was read.
  void run(const std::vector<Rectangle>& scene_a, const std::vector<Rectangle>& scene_b,
           const cv::Mat& drop_b, const cv::Mat& background_b, CrossCameraFillConfig config = on()) {
    views.clear();
    for (int i = 0; i < 2; ++i) {
      cv::Mat index;
      cv::Mat depth = castDepth(cameras[std::size_t(i)], i == 0 ? scene_a : scene_b, &index);
      if (i == 1) depth.setTo(0.0f, drop_b);
      cv::Mat mask = (index == 0) & (depth > 0.0f);
      views.push_back({depth, mask, i == 1 ? background_b : cv::Mat()});
    }
    out = CrossCameraFill(cameras, config).apply(views, &counts);
  }
};

cv::Mat patch(int x, int y, int w, int h) {
  cv::Mat m(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
  m(cv::Rect(x, y, w, h)).setTo(255);
  return m;
}

// B's sensor reads nothing on a 12x12 patch of the visitor; A read it, so the patch is filled
// with the visitor's true depth and joins B's mask. The geometry is exact; the error left is a
// splat's width (up to 3 pixels) along the visitor's slope as B sees it, under a centimetre.
TEST(CrossCameraFill, FillsAHoleInOneCameraFromAnother) {
  TwoCameras s;
  const std::vector<Rectangle> scene{kVisitor, kHallWall};
  cv::Mat index_b;
  const cv::Mat truth_b = castDepth(s.cameras[1], scene, &index_b);
  const cv::Mat hole = patch(42, 30, 12, 12) & (index_b == 0);
  ASSERT_EQ(cv::countNonZero(hole), 144) << "the patch must lie on the visitor";
  s.run(scene, scene, hole, castDepth(s.cameras[1], {kHallWall}));

  long filled = 0;
  double worst = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      if (!hole.at<std::uint8_t>(y, x)) continue;
      const float d = s.out[1].at<float>(y, x);
      if (!(d > 0.0f)) continue;
      ++filled;
      worst = std::max(worst, double(std::abs(d - truth_b.at<float>(y, x))));
      EXPECT_EQ(s.views[1].mask.at<std::uint8_t>(y, x), 255);
    }
  EXPECT_EQ(s.counts[1].filled, filled);
  EXPECT_GE(filled, 140);
  EXPECT_LT(worst, 0.01);
  // A measured depth is never changed: outside the hole B's depth is its own.
  cv::Mat changed = (s.out[1] != s.views[1].depth) & ~hole;
  EXPECT_EQ(cv::countNonZero(changed), 0);

  CrossCameraFillConfig off;
  off.enabled = false;
  s.run(scene, scene, hole, castDepth(s.cameras[1], {kHallWall}), off);
  EXPECT_EQ(cv::countNonZero((s.out[1] > 0.0f) & hole), 0);
  EXPECT_EQ(s.counts[1].filled, 0);
}

// The adversary: the visitor stands behind a wall as B sees it, in full view of A. B reads the
// wall except for scattered single-pixel dropouts; where B reads it, nothing is filled, and no
// dropout is filled either (B's own nearer wall around it hides the visitor). Without the
// visibility check the visitor is painted onto B's wall: the check is what keeps it out.
TEST(CrossCameraFill, NeverPaintsAVisitorHiddenBehindAWallThatBReads) {
  TwoCameras s;
  const std::vector<Rectangle> scene_a{kVisitor, kHallWall};
  const std::vector<Rectangle> scene_b{kVisitor, kWallBeforeB, kHallWall};
  cv::Mat index_b;
  castDepth(s.cameras[1], scene_b, &index_b);
  ASSERT_EQ(cv::countNonZero(index_b == 0), 0) << "the wall must hide the visitor from B";
  cv::Mat dropouts(kHeight, kWidth, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < kHeight; y += 3)
    for (int x = (y / 3) % 3; x < kWidth; x += 3) dropouts.at<std::uint8_t>(y, x) = 255;
  dropouts &= (index_b == 1);  // on the wall

  s.run(scene_a, scene_b, dropouts, cv::Mat());
  EXPECT_EQ(s.counts[1].filled, 0);
  EXPECT_EQ(s.counts[1].confirmed, 0);
  EXPECT_EQ(cv::countNonZero(s.views[1].mask), 0);
  EXPECT_EQ(cv::countNonZero(s.out[1] != s.views[1].depth), 0);

  CrossCameraFillConfig unchecked = TwoCameras::on();
  unchecked.visibility_radius_px = 0;
  s.run(scene_a, scene_b, dropouts, cv::Mat(), unchecked);
  EXPECT_GT(s.counts[1].filled, 20) << "the adversary must be real: A's visitor lands on B's wall";
}

// The same wall, but B reads nothing of it (a dark, matte wall) and knows it from the background
// it learned: the learned depth hides the visitor.
TEST(CrossCameraFill, NeverPaintsAVisitorBehindTheLearnedBackground) {
  TwoCameras s;
  const std::vector<Rectangle> scene_a{kVisitor, kHallWall};
  const std::vector<Rectangle> scene_b{kVisitor, kWallBeforeB, kHallWall};
  cv::Mat index_b;
  castDepth(s.cameras[1], scene_b, &index_b);
  const cv::Mat unread_wall = index_b == 1;
  const cv::Mat background_b = castDepth(s.cameras[1], {kWallBeforeB, kHallWall});

  s.run(scene_a, scene_b, unread_wall, background_b);
  EXPECT_EQ(s.counts[1].filled, 0);
  EXPECT_EQ(cv::countNonZero(s.views[1].mask), 0);

  s.run(scene_a, scene_b, unread_wall, cv::Mat());
  EXPECT_GT(s.counts[1].filled, 50) << "without the background the adversary must win";
}

// B reads the visitor but its mask lost a strip (the opening removes thin limbs): where B's own
// depth agrees with A's projected visitor the pixel joins B's mask, its depth B's own.
TEST(CrossCameraFill, MeasuredPixelsAgreeingWithAnotherCameraJoinTheMask) {
  TwoCameras s;
  const std::vector<Rectangle> scene{kVisitor, kHallWall};
  s.run(scene, scene, cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(0)), castDepth(s.cameras[1], {kHallWall}));
  const cv::Mat full_mask = s.views[1].mask.clone();
  ASSERT_GT(cv::countNonZero(full_mask), 300);

  // Rerun with a strip of B's mask removed before the step.
  std::vector<CrossCameraView> views;
  for (const CrossCameraView& v : s.views) views.push_back({v.depth, v.mask.clone(), v.background_depth});
  views[1].mask(cv::Rect(0, 34, kWidth, 3)).setTo(0);
  const cv::Mat lost = full_mask & ~views[1].mask;
  ASSERT_GT(cv::countNonZero(lost), 20);
  std::vector<CrossCameraCounts> counts;
  const std::vector<cv::Mat> out = CrossCameraFill(s.cameras, TwoCameras::on()).apply(views, &counts);
  // A's silhouette pixels are not sent, so the strip's ends next to it may stay out.
  const int rejoined = cv::countNonZero(lost & views[1].mask);
  EXPECT_GE(rejoined, cv::countNonZero(lost) * 8 / 10);
  EXPECT_EQ(counts[1].confirmed, rejoined);
  EXPECT_EQ(cv::countNonZero(views[1].mask & ~full_mask), 0) << "only the visitor joins";
  EXPECT_EQ(cv::countNonZero(out[1] != views[1].depth), 0);
  EXPECT_EQ(counts[1].filled, 0);
}

TEST(CrossCameraFill, RefusesBadSettingsAndMismatchedViews) {
  const std::vector<CameraModel> cameras{camera(-1.0f), camera(1.0f)};
  CrossCameraFillConfig bad = TwoCameras::on();
  bad.max_splat_px = 0;
  EXPECT_THROW(CrossCameraFill(cameras, bad), Error);
  bad = {};
  bad.tolerance_m = 0.0f;
  EXPECT_THROW(CrossCameraFill(cameras, bad), Error);
  const CrossCameraFill fill(cameras);
  std::vector<CrossCameraView> one(1);
  EXPECT_THROW(fill.apply(one), Error);
  std::vector<CrossCameraView> small(2);
  small[0] = {cv::Mat(10, 10, CV_32FC1, cv::Scalar(1.0f)), cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)),
              cv::Mat()};
  EXPECT_THROW(fill.apply(small), Error);
  // A missing camera (empty view) is skipped, not an error.
  std::vector<CrossCameraView> missing(2);
  EXPECT_EQ(fill.apply(missing).size(), 2u);
}

}  // namespace
}  // namespace holo::depthfilter
