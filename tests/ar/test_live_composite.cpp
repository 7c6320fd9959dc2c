// The live AR composite refined while still (ar/live_composite.hpp) on the sphere-on-a-plane scene
// (ar_test_scene.hpp): the camera's frame is the real scene path traced, its depth the plane's.
// Counted in frames, never in wall-clock time.
#include <gtest/gtest.h>

#include <iostream>

#include <vector>

#include "ar_test_scene.hpp"
#include "holo/ar/live_composite.hpp"
#include "holo/ar/local_path_tracing.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::ar {
namespace {

using test::camera;
using test::plane;
using test::sphereRelic;
using test::sunnyPanorama;

// The camera's frame of the plane: its radiance path traced (sRGB, exposure 1), its depth exact.
RgbdFrame planeFrame(const CameraModel& view, const cv::Mat& panorama) {
  const reflect::Environment environment(panorama);
  const LocalScene scene(plane(), Model{}, environment);
  CompositeSettings s;
  s.spp = 64;
  s.seed = 99;
  RgbdFrame frame;
  frame.colour = linearToSrgb8(renderLocalScene(scene, SceneContent::kReal, view, s).radiance);
  frame.depth = cv::Mat::zeros(view.height(), view.width(), CV_32FC1);
  const vec3 forward = glm::normalize(vec3(view.T_world_camera()[2]));
  for (int y = 0; y < view.height(); ++y)
    for (int x = 0; x < view.width(); ++x) {
      const Ray ray = view.ray({static_cast<float>(x), static_cast<float>(y)});
      if (ray.direction.y >= 0.0f) continue;
      const float t = -ray.origin.y / ray.direction.y;
      const vec3 p = ray.origin + t * ray.direction;
      if (std::abs(p.x) < 1.0f && std::abs(p.z) < 1.0f)
        frame.depth.at<float>(y, x) = t * glm::dot(ray.direction, forward);
    }
  return frame;
}

double rmse(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a, b, cv::NORM_L2) / std::sqrt(static_cast<double>(a.total() * a.channels()));
}

LiveCompositeSettings oneSamplePerFrame() {
  LiveCompositeSettings s;
  s.view.composite.spp = 1;
  s.view.composite.seed = 5;
  return s;
}

struct Fixture {
  CameraModel view = camera();
  cv::Mat panorama = sunnyPanorama();
  Model relic = sphereRelic();
  RgbdFrame frame = planeFrame(view, panorama);
  // The composite of this frame at 512 samples, unfiltered: what a still view converges to.
  cv::Mat converged() const {
    LiveCompositeSettings s = oneSamplePerFrame();
    s.view.composite.spp = 512;
    s.view.composite.seed = 1234;
    LiveComposite reference(0, view, panorama, relic, s);
    return reference.add(frame).unfiltered;
  }
};

// Errors against the converged composite over `frames` still frames.
std::vector<double> stillErrors(const Fixture& f, const LiveCompositeSettings& settings, int frames,
                                const cv::Mat& converged, bool filtered) {
  LiveComposite live(0, f.view, f.panorama, f.relic, settings);
  std::vector<double> errors;
  for (int n = 0; n < frames; ++n) {
    const LiveCompositeFrame out = live.add(f.frame);
    EXPECT_EQ(out.reset, n == 0);
    // Encoded over the change's box only, the image is the whole radiance's encoding.
    EXPECT_EQ(cv::norm(out.image, linearToSrgb8(out.radiance), cv::NORM_INF), 0.0);
    errors.push_back(rmse(filtered ? out.radiance : out.unfiltered, converged));
  }
  return errors;
}

TEST(LiveComposite, AStillViewRefinesFrameByFrame) {
  const Fixture f;
  const cv::Mat converged = f.converged();
  const std::vector<double> errors = stillErrors(f, oneSamplePerFrame(), 16, converged, false);
  // Falls with the samples: each doubling of the frames lowers it (1, 2, 4, 8, 16 frames).
  for (const int n : {1, 2, 4, 8})
    EXPECT_LT(errors[static_cast<std::size_t>(2 * n - 1)], errors[static_cast<std::size_t>(n - 1)])
        << "frames " << n << " and " << 2 * n;
  EXPECT_LT(errors[15], 0.4 * errors[0]) << "16 samples: about a quarter of one sample's noise";
  // What is shown (the change filtered) refines too.
  const std::vector<double> shown = stillErrors(f, oneSamplePerFrame(), 16, converged, true);
  EXPECT_LT(shown[15], 0.6 * shown[0]);
  std::cout << "error at frames 1, 2, 4, 8, 16: " << errors[0] << ", " << errors[1] << ", " << errors[3]
            << ", " << errors[7] << ", " << errors[15] << "; shown " << shown[0] << " -> " << shown[15]
            << "\n";
}

// With the accumulation switched off (one sample is all a view keeps) the 16th still frame is no
// better than the first: the refinement is what lowers the error.
TEST(LiveComposite, WithoutAccumulationAStillViewDoesNotImprove) {
  const Fixture f;
  const cv::Mat converged = f.converged();
  LiveCompositeSettings off = oneSamplePerFrame();
  off.max_samples = 1;
  const std::vector<double> flat = stillErrors(f, off, 16, converged, false);
  const std::vector<double> refined = stillErrors(f, oneSamplePerFrame(), 16, converged, false);
  EXPECT_DOUBLE_EQ(flat[15], flat[0]);
  EXPECT_LT(refined[15], 0.5 * flat[15]);
}

TEST(LiveComposite, AChangedImageResetsInTheNextFrameAndSensorNoiseDoesNot) {
  Fixture f;
  LiveComposite live(0, f.view, f.panorama, f.relic, oneSamplePerFrame());
  for (int n = 0; n < 6; ++n) live.add(f.frame);
  ASSERT_EQ(live.samples(), 6);

  // The sensor's noise (up to 3 codes per pixel) is not a change: the view keeps refining.
  RgbdFrame noisy = f.frame;
  noisy.colour = f.frame.colour.clone();
  cv::Mat noise(noisy.colour.size(), CV_8UC3);
  cv::randu(noise, cv::Scalar::all(0), cv::Scalar::all(4));
  noisy.colour += noise;
  const LiveCompositeFrame kept = live.add(noisy);
  EXPECT_FALSE(kept.reset);
  EXPECT_EQ(kept.samples, 7);

  // Something walks into a quarter of the picture: the next frame starts again.
  RgbdFrame walked = f.frame;
  walked.colour = f.frame.colour.clone();
  walked.colour(cv::Rect(0, 0, f.view.width() / 2, f.view.height() / 2)).setTo(cv::Scalar(20, 40, 200));
  const LiveCompositeFrame changed = live.add(walked);
  EXPECT_TRUE(changed.reset);
  EXPECT_EQ(changed.samples, 1);
  EXPECT_GT(changed.changed, 0.2);
  EXPECT_EQ(live.add(walked).samples, 2) << "still again: refining the new picture";

  // The surface moves (depth 10% nearer over the whole image): a change too.
  RgbdFrame nearer = walked;
  nearer.depth = walked.depth * 0.9f;
  EXPECT_TRUE(live.add(nearer).reset);

  // A new relic: the next frame starts again although the picture is the same.
  live.add(nearer);
  live.setRelic(f.relic);
  EXPECT_TRUE(live.add(nearer).reset);
}

// A change of colour alone (the depth still) keeps the depth surface and its ray scene, and the
// new accumulation is exactly the one a view started on that frame makes; a depth change builds a
// new surface.
TEST(LiveComposite, AColourChangeKeepsTheDepthSurfaceAndGivesTheSameComposite) {
  Fixture f;
  LiveComposite live(0, f.view, f.panorama, f.relic, oneSamplePerFrame());
  for (int n = 0; n < 3; ++n) live.add(f.frame);
  ASSERT_EQ(live.surfacesBuilt(), 1);
  RgbdFrame repainted = f.frame;
  repainted.colour = f.frame.colour.clone();
  repainted.colour(cv::Rect(0, 0, f.view.width() / 2, f.view.height() / 2)).setTo(cv::Scalar(20, 40, 200));
  LiveComposite fresh(0, f.view, f.panorama, f.relic, oneSamplePerFrame());
  for (int n = 0; n < 3; ++n) {
    const LiveCompositeFrame kept = live.add(repainted);
    const LiveCompositeFrame made = fresh.add(repainted);
    EXPECT_EQ(kept.reset, n == 0);
    EXPECT_EQ(kept.samples, n + 1);
    EXPECT_EQ(cv::norm(kept.unfiltered, made.unfiltered, cv::NORM_INF), 0.0) << "frame " << n;
    EXPECT_EQ(cv::norm(kept.image, made.image, cv::NORM_INF), 0.0) << "frame " << n;
  }
  EXPECT_EQ(live.surfacesBuilt(), 1);
  RgbdFrame nearer = repainted;
  nearer.depth = repainted.depth * 0.9f;
  EXPECT_TRUE(live.add(nearer).reset);
  EXPECT_EQ(live.surfacesBuilt(), 2);
}

TEST(LiveComposite, RefusesACameraWithoutDepthNamingIt) {
  const Fixture f;
  LiveComposite live(3, f.view, f.panorama, f.relic, oneSamplePerFrame());
  RgbdFrame no_depth = f.frame;
  no_depth.depth = cv::Mat();
  try {
    live.add(no_depth);
    FAIL() << "a frame without depth was composited";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("camera 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("depth"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace holo::ar
