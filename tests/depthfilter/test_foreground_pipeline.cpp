#include <gtest/gtest.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/depthfilter/foreground_pipeline.hpp"
#include "synthetic_rgbd.hpp"

namespace holo::depthfilter {
namespace {

constexpr int kCameras = 4;

// Four cameras on the sides of the pyramid base, looking outward (face f at azimuth f * 90 deg).
std::vector<CameraModel> cameras(const test::SyntheticScene& scene) {
  std::vector<CameraModel> out;
  for (int f = 0; f < kCameras; ++f) {
    const float a = float(f) * 1.5707963f;
    const vec3 outward(std::sin(a), 0.0f, std::cos(a));
    out.emplace_back(scene.intrinsics(), lookAtCameraToWorld(0.3f * outward, 2.0f * outward));
  }
  return out;
}

struct Rig {
  test::SyntheticScene scene;
  ForegroundPipeline pipeline;
  std::uint64_t frame = 0;

  explicit Rig(ForegroundPipelineConfig config = quickConfig()) : pipeline(cameras(scene), config) {
    test::SyntheticScene empty = scene;
    empty.objects = false;
    for (int t = 0; t < 10; ++t) {
      std::array<RgbdFrame, kCameras> background;
      for (int c = 0; c < kCameras; ++c)
        background[std::size_t(c)] = empty.render(t, 100 + std::uint64_t(c)).frame;
      pipeline.learnBackground(background);
    }
  }
  static ForegroundPipelineConfig quickConfig() {
    ForegroundPipelineConfig config;
    config.filter.learning_frames = 5;
    config.exposure = 2.0f;
    return config;
  }
  std::array<test::SyntheticFrame, kCameras> render(int t) const {
    std::array<test::SyntheticFrame, kCameras> out;
    for (int c = 0; c < kCameras; ++c) {
      out[std::size_t(c)] = scene.render(t, 200 + std::uint64_t(c));
      out[std::size_t(c)].frame.camera_id = c;
    }
    return out;
  }
  static std::array<RgbdFrame, kCameras> framesOf(const std::array<test::SyntheticFrame, kCameras>& f) {
    std::array<RgbdFrame, kCameras> out;
    for (int c = 0; c < kCameras; ++c) out[std::size_t(c)] = f[std::size_t(c)].frame;
    return out;
  }
};

TEST(ForegroundPipeline, BackProjectsFilteredForegroundOfEveryCameraIntoTheWorld) {
  Rig rig;
  ForegroundCloud cloud;
  std::array<test::SyntheticFrame, kCameras> truth;
  for (int t = 0; t < 12; ++t) {
    truth = rig.render(t);
    cloud = rig.pipeline.process(Rig::framesOf(truth));
  }
  ASSERT_FALSE(rig.pipeline.filter(0).learning());
  EXPECT_EQ(cloud.sequence, 11);
  const std::vector<CameraModel> models = cameras(rig.scene);
  std::array<long, kCameras> per_camera{};
  double error_sum = 0.0, radiance_error = 0.0;
  long interior = 0, border = 0;
  for (const ForegroundPoint& p : cloud.points) {
    ASSERT_LT(p.camera, kCameras);
    ASSERT_TRUE(isFinite(p.position) && isFinite(p.radiance));
    ASSERT_GT(p.weight, 0.0f);
    ASSERT_LE(p.weight, 1.0f);
    ++per_camera[p.camera];
    const test::SyntheticFrame& f = truth[p.camera];
    if (p.weight < 1.0f) {
      ++border;
      EXPECT_EQ(rig.pipeline.lastResult(p.camera).mask.at<std::uint8_t>(p.y, p.x), 0);  // outside phi_i
      continue;
    }
    // Colour: the camera's sRGB linearised and divided by the exposure (2).
    const cv::Vec3b bgr = f.frame.colour.at<cv::Vec3b>(p.y, p.x);
    radiance_error =
        std::max(radiance_error, double(std::abs(p.radiance.r - srgbToLinear(bgr[2] / 255.0f) / 2.0f)));
    // Position: where the true depth puts that pixel.
    if (f.true_mask.at<std::uint8_t>(p.y, p.x) == 0) continue;
    const vec3 expected = models[p.camera].unproject(vec2(p.x, p.y), f.true_depth.at<float>(p.y, p.x));
    error_sum += glm::length(p.position - expected);
    ++interior;
  }
  for (int c = 0; c < kCameras; ++c) EXPECT_GT(per_camera[std::size_t(c)], 3000) << "camera " << c;
  EXPECT_GT(border, 1000);
  EXPECT_LT(radiance_error, 1e-5);
  EXPECT_LT(error_sum / double(interior), 0.01);  // mean 3D error below 1 cm
  // Camera 1 looks along +X: its points lie on that side of the pyramid.
  float min_x_of_camera_1 = INFINITY;
  for (const ForegroundPoint& p : cloud.points)
    if (p.camera == 1) min_x_of_camera_1 = std::min(min_x_of_camera_1, p.position.x);
  EXPECT_GT(min_x_of_camera_1, 1.0f);
}

TEST(ForegroundPipeline, ForgetBackgroundLearnsTheSceneAsItIsNow) {
  // The technician's "relearn the background": what stood in front of the cameras when it was
  // relearnt (moved furniture) is background from then on.
  Rig rig;
  const std::array<RgbdFrame, kCameras> frames = Rig::framesOf(rig.render(0));
  std::size_t before = 0;
  for (int k = 0; k < 8; ++k) before = rig.pipeline.process(frames).points.size();
  ASSERT_GT(before, 0u);
  rig.pipeline.forgetBackground();
  for (int k = 0; k < 10; ++k) rig.pipeline.learnBackground(frames);
  std::size_t after = 0;
  for (int k = 0; k < 8; ++k) after = rig.pipeline.process(frames).points.size();
  EXPECT_LT(after * 10, before) << "before " << before << ", after " << after;
}

TEST(ForegroundPipeline, MissingCameraFrameContributesNothingAndOthersGoOn) {
  Rig rig;
  for (int t = 0; t < 8; ++t) rig.pipeline.process(Rig::framesOf(rig.render(t)));
  std::array<RgbdFrame, kCameras> frames = Rig::framesOf(rig.render(8));
  frames[2] = RgbdFrame{};
  const ForegroundCloud cloud = rig.pipeline.process(frames);
  EXPECT_FALSE(rig.pipeline.lastResult(2).present);
  std::array<long, kCameras> per_camera{};
  for (const ForegroundPoint& p : cloud.points) ++per_camera[p.camera];
  EXPECT_EQ(per_camera[2], 0);
  EXPECT_GT(per_camera[0], 3000);
  // The camera comes back next frame.
  const ForegroundCloud next = rig.pipeline.process(Rig::framesOf(rig.render(9)));
  per_camera = {};
  for (const ForegroundPoint& p : next.points) ++per_camera[p.camera];
  EXPECT_GT(per_camera[2], 3000);
}

TEST(ForegroundPipeline, HardInputsStayFiniteAndBadInputIsRefused) {
  Rig rig;
  for (int t = 0; t < 10; ++t) {
    std::array<RgbdFrame, kCameras> frames = Rig::framesOf(rig.render(t));
    frames[0].depth.setTo(std::nanf(""));
    frames[1].depth.setTo(0.0f);
    frames[3].depth(cv::Rect(0, 0, 100, 100)).setTo(std::numeric_limits<float>::infinity());
    const ForegroundCloud cloud = rig.pipeline.process(frames);
    for (const ForegroundPoint& p : cloud.points) {
      ASSERT_TRUE(isFinite(p.position) && isFinite(p.radiance));
      ASSERT_NE(p.camera, 1);  // no depth anywhere: nothing to back-project
    }
  }
  std::array<RgbdFrame, kCameras> frames = Rig::framesOf(rig.render(11));
  EXPECT_THROW(rig.pipeline.process(std::span<const RgbdFrame>(frames.data(), 3)), Error);
  cv::resize(frames[0].colour, frames[0].colour, cv::Size(100, 50));
  EXPECT_THROW(rig.pipeline.process(frames), Error);
  EXPECT_THROW(ForegroundPipeline({}, {}), Error);
}

// The foreground at half resolution covers what the camera's own does, in the camera's pixels:
// the expanded masks keep the true objects' pixels within 3 points of recall, the points lie where
// the true depth puts their block's centre and keep full-size pixel coordinates, a quarter as many.
TEST(ForegroundPipeline, HalfScaleCoversTheForegroundInTheCamerasPixels) {
  ForegroundPipelineConfig half_config = Rig::quickConfig();
  half_config.scale = 2;
  Rig full, half(half_config);
  ForegroundCloud full_cloud, half_cloud;
  std::array<test::SyntheticFrame, kCameras> truth;
  std::array<long, 2> covered{}, actual{};
  for (int t = 0; t < 12; ++t) {
    truth = full.render(t);
    full_cloud = full.pipeline.process(Rig::framesOf(truth));
    half_cloud = half.pipeline.process(Rig::framesOf(truth));
    if (t < 6) continue;
    for (int c = 0; c < kCameras; ++c) {
      const cv::Mat& true_mask = truth[std::size_t(c)].true_mask;
      const cv::Mat& half_mask = half.pipeline.lastResult(std::size_t(c)).mask;
      ASSERT_EQ(half_mask.size() * 2, true_mask.size());
      const cv::Mat masks[2] = {full.pipeline.lastResult(std::size_t(c)).mask,
                                expandedToFull(half_mask, true_mask.size())};
      for (int s = 0; s < 2; ++s) {
        covered[std::size_t(s)] += cv::countNonZero(masks[s] & true_mask);
        actual[std::size_t(s)] += cv::countNonZero(true_mask);
      }
    }
  }
  const double full_recall = double(covered[0]) / double(actual[0]);
  const double half_recall = double(covered[1]) / double(actual[1]);
  std::printf("true-mask recall: full %.4f half %.4f\n", full_recall, half_recall);
  EXPECT_GT(full_recall, 0.9);
  EXPECT_GT(half_recall, full_recall - 0.03) << "full " << full_recall;
  const std::vector<CameraModel> models = cameras(full.scene);
  double error_sum = 0.0;
  long interior = 0;
  for (const ForegroundPoint& p : half_cloud.points) {
    ASSERT_LT(p.x, full.scene.width);
    ASSERT_LT(p.y, full.scene.height);
    ASSERT_EQ(p.x % 2, 0);
    ASSERT_EQ(p.y % 2, 0);
    const test::SyntheticFrame& f = truth[p.camera];
    if (p.weight < 1.0f || f.true_mask.at<std::uint8_t>(p.y, p.x) == 0) continue;
    // The block's centre at the depth the reduced frame read (its top-left pixel's).
    const vec3 expected = models[p.camera].unproject(vec2(float(p.x) + 0.5f, float(p.y) + 0.5f),
                                                     f.true_depth.at<float>(p.y, p.x));
    error_sum += glm::length(p.position - expected);
    ++interior;
  }
  ASSERT_GT(interior, 1000);
  EXPECT_LT(error_sum / double(interior), 0.01);  // mean 3D error below 1 cm
  const double point_ratio = double(half_cloud.points.size()) / double(full_cloud.points.size());
  std::printf("half: mean 3D error %.4f m over %ld points, %.3f of full's points\n",
              error_sum / double(interior), interior, point_ratio);
  EXPECT_GT(point_ratio, 0.15);
  EXPECT_LT(point_ratio, 0.45);
}

// The half-resolution foreground with its outline redrawn at the camera's resolution
// (full_size_outline) against the same foreground repeated over its blocks (the stage off):
// scored against the true objects in the camera's pixels, it outputs fewer than half the depths
// off the objects and covers no fewer of their pixels; its points include the camera's odd
// pixels, and number between the half-resolution and the camera-resolution foreground's.
TEST(ForegroundPipeline, FullSizeOutlineLeavesFewerDepthsOffTheObjectsThanBlocks) {
  ForegroundPipelineConfig blocks_config = Rig::quickConfig();
  blocks_config.scale = 2;
  ForegroundPipelineConfig outline_config = blocks_config;
  outline_config.full_size_outline = true;
  Rig blocks(blocks_config), outline(outline_config), full;
  std::array<long, 3> off{}, covered{};
  long actual = 0;
  ForegroundCloud outline_cloud, full_cloud;
  for (int t = 0; t < 12; ++t) {
    const std::array<test::SyntheticFrame, kCameras> truth = blocks.render(t);
    blocks.pipeline.process(Rig::framesOf(truth));
    outline_cloud = outline.pipeline.process(Rig::framesOf(truth));
    full_cloud = full.pipeline.process(Rig::framesOf(truth));
    if (t < 6) continue;
    for (int c = 0; c < kCameras; ++c) {
      const cv::Mat& true_mask = truth[std::size_t(c)].true_mask;
      const cv::Mat& outline_depth = outline.pipeline.lastResult(std::size_t(c)).depth;
      ASSERT_EQ(outline_depth.size(), true_mask.size());
      ASSERT_EQ(outline.pipeline.lastResult(std::size_t(c)).mask.size(), true_mask.size());
      const cv::Mat depths[3] = {
          expandedToFull(blocks.pipeline.lastResult(std::size_t(c)).depth, true_mask.size()), outline_depth,
          full.pipeline.lastResult(std::size_t(c)).depth};
      for (int s = 0; s < 3; ++s) {
        const cv::Mat has = depths[s] > 0.0f;
        off[std::size_t(s)] += cv::countNonZero(has & ~true_mask);
        covered[std::size_t(s)] += cv::countNonZero(has & true_mask);
      }
      actual += cv::countNonZero(true_mask);
    }
  }
  std::printf(
      "off the objects: blocks %ld outline %ld full %ld; covered: blocks %ld outline %ld full %ld of %ld\n",
      off[0], off[1], off[2], covered[0], covered[1], covered[2], actual);
  EXPECT_LT(double(off[1]), 0.5 * double(off[0]));
  EXPECT_GE(double(covered[1]), 0.99 * double(covered[0]));
  bool odd_pixel = false;
  for (const ForegroundPoint& p : outline_cloud.points) {
    ASSERT_LT(p.x, outline.scene.width);
    ASSERT_LT(p.y, outline.scene.height);
    odd_pixel |= (p.x % 2) != 0 || (p.y % 2) != 0;
  }
  EXPECT_TRUE(odd_pixel);
  // A repeated block gives one point, a redrawn block one per pixel: between the two scales.
  const double point_ratio = double(outline_cloud.points.size()) / double(full_cloud.points.size());
  std::printf("outline points %.3f of full's\n", point_ratio);
  EXPECT_GT(point_ratio, 0.3);
  EXPECT_LT(point_ratio, 0.8);
}

TEST(ForegroundPipeline, ForegroundScaleOutOfRangeOrNotDividingTheCameraIsRefused) {
  const test::SyntheticScene scene;
  for (int scale : {0, 3}) {
    ForegroundPipelineConfig config;
    config.scale = scale;
    try {
      ForegroundPipeline pipeline(cameras(scene), config);
      ADD_FAILURE() << "accepted scale " << scale;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("foreground scale: expected an integer in [1, 2]"),
                std::string::npos)
          << e.what();
    }
  }
  test::SyntheticScene odd = scene;
  odd.width = 321;
  ForegroundPipelineConfig config;
  config.scale = 2;
  EXPECT_THROW(ForegroundPipeline(cameras(odd), config), Error);
  config.scale = 1;
  EXPECT_NO_THROW(ForegroundPipeline(cameras(odd), config));
}

// The flow, the filtered depth and the border layer reuse their buffers from frame to frame when nobody holds
// the last ones, clearing only the box written before. A pipeline whose every result is kept (so each frame
// gets fresh zero images) must give the same images bit for bit while the visitor moves, and the kept results
// must stay as they were.
TEST(ForegroundPipeline, ReusedOutputBuffersGiveTheSameImagesAndKeptResultsStay) {
  Rig reused, fresh;
  std::vector<std::array<cv::Mat, 4>> kept, kept_copies;
  const auto same = [](const cv::Mat& a, const cv::Mat& b) {
    if (a.size() != b.size() || a.type() != b.type()) return false;
    for (int y = 0; y < a.rows; ++y)
      if (std::memcmp(a.ptr(y), b.ptr(y), a.cols * a.elemSize()) != 0) return false;
    return true;
  };
  int compared = 0;
  for (int t = 0; t < 12; ++t) {
    reused.pipeline.process(Rig::framesOf(reused.render(t)));
    fresh.pipeline.process(Rig::framesOf(fresh.render(t)));
    for (std::size_t c = 0; c < kCameras; ++c) {
      const CameraForeground& r = reused.pipeline.lastResult(c);
      const CameraForeground& f = fresh.pipeline.lastResult(c);
      ASSERT_TRUE(same(r.depth, f.depth)) << "frame " << t << " camera " << c;
      ASSERT_TRUE(same(r.flow, f.flow)) << "frame " << t << " camera " << c;
      ASSERT_TRUE(same(r.border.weight, f.border.weight)) << "frame " << t << " camera " << c;
      ASSERT_TRUE(same(r.border.depth, f.border.depth)) << "frame " << t << " camera " << c;
      compared += cv::countNonZero(r.depth) > 0;
      kept.push_back({f.depth, f.flow, f.border.weight, f.border.depth});
      kept_copies.push_back(
          {f.depth.clone(), f.flow.clone(), f.border.weight.clone(), f.border.depth.clone()});
    }
  }
  EXPECT_GT(compared, 20);  // most frames have a filtered foreground to compare
  for (std::size_t i = 0; i < kept.size(); ++i) {
    for (std::size_t k = 0; k < 4; ++k) EXPECT_TRUE(same(kept[i][k], kept_copies[i][k])) << i << " " << k;
  }
}

TEST(ForegroundPipeline, ParallelAndSerialGiveTheSameCloud) {
  ForegroundPipelineConfig serial = Rig::quickConfig();
  serial.parallel = false;
  Rig a, b(serial);
  ForegroundCloud ca, cb;
  for (int t = 0; t < 8; ++t) {
    ca = a.pipeline.process(Rig::framesOf(a.render(t)));
    cb = b.pipeline.process(Rig::framesOf(b.render(t)));
  }
  ASSERT_EQ(ca.points.size(), cb.points.size());
  for (std::size_t i = 0; i < ca.points.size(); ++i) {
    ASSERT_EQ(ca.points[i].position, cb.points[i].position);
    ASSERT_EQ(ca.points[i].camera, cb.points[i].camera);
  }
}

}  // namespace
}  // namespace holo::depthfilter
