// The simulated museum's cameras as CameraSources: deterministic content, pacing, end of stream.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "holo/capture/capture_config.hpp"
#include "holo/capture/capture_thread.hpp"
#include "holo/core/error.hpp"
#include "holo/sim/museum.hpp"
#include "holo/simulated/simulated_source.hpp"

using namespace holo;
using namespace holo::capture;
using namespace holo::simulated;
using namespace std::chrono_literals;

namespace {

// Small frames keep the test quick; everything else is the built-in scene.
std::shared_ptr<const sim::Museum> smallMuseum(std::uint64_t seed = 1, float fps = 20) {
  sim::SceneDescription d = sim::loadScene("room");
  d.camera.width = 96;
  d.camera.height = 54;
  d.camera.fps = fps;
  d.seed = seed;
  return std::make_shared<const sim::Museum>(d);
}

bool identical(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

}  // namespace

TEST(SimulatedSource, FramesAreDeterministicAndCarrySceneTime) {
  const auto museum = smallMuseum();
  SimulatedSource a(museum, 1, {.paced = false, .first_frame = 0, .frame_count = 3});
  SimulatedSource b(smallMuseum(), 1, {.paced = false, .first_frame = 0, .frame_count = 3});
  a.open();
  a.start();
  b.open();
  b.start();
  for (int n = 0; n < 3; ++n) {
    const GrabResult fa = a.grab(1s);
    const GrabResult fb = b.grab(1s);
    ASSERT_EQ(fa.status, GrabStatus::Ok) << fa.message;
    ASSERT_EQ(fb.status, GrabStatus::Ok) << fb.message;
    EXPECT_TRUE(identical(fa.frame.colour, fb.frame.colour)) << "frame " << n;
    EXPECT_TRUE(identical(fa.frame.depth, fb.frame.depth)) << "frame " << n;
    EXPECT_EQ(fa.frame.colour.size(), cv::Size(96, 54));
    EXPECT_EQ(fa.frame.camera_id, 1);
    EXPECT_EQ(fa.frame.sequence, static_cast<std::uint64_t>(n));
    EXPECT_EQ(fa.frame.device_time.count(), n * 50'000'000);  // n / 20 fps
    EXPECT_NO_THROW(fa.frame.validate());
  }
  EXPECT_EQ(a.grab(1s).status, GrabStatus::EndOfStream);
  ASSERT_TRUE(a.cameraModel().has_value());
  EXPECT_EQ(a.cameraModel()->width(), 96);
  EXPECT_EQ(a.serial(), "SIM-room-1");

  // Another seed moves the visitors and the noise: the frames differ.
  SimulatedSource c(smallMuseum(2), 1, {.paced = false, .first_frame = 0, .frame_count = 1});
  c.start();
  a.start();
  EXPECT_FALSE(identical(a.grab(1s).frame.depth, c.grab(1s).frame.depth));
}

TEST(SimulatedSource, PacedFramesComeNoEarlierThanTheirTime) {
  // 1 fps: the next frame's second leaves a busy machine ample time for the 1 ms wait before it.
  SimulatedSource s(smallMuseum(1, 1.0f), 0, {.paced = true, .first_frame = 10, .frame_count = -1});
  const auto start = Clock::now();  // before the source's own start, so no later than it
  s.start();
  ASSERT_EQ(s.grab(1s).status, GrabStatus::Ok);  // frame 10 is due at once
  // Frame 11 is due 1 s after start: a 1 ms wait times out without rendering it.
  EXPECT_EQ(s.grab(1ms).status, GrabStatus::Timeout);
  const GrabResult next = s.grab(30s);
  ASSERT_EQ(next.status, GrabStatus::Ok);
  EXPECT_GE(Clock::now() - start, 1s);
  EXPECT_EQ(next.frame.sequence, 1u);
  EXPECT_EQ(next.frame.device_time.count(), 11'000'000'000);
}

// The check camera (4) sees the hall from a tripod, the relic's place in view: its frames have depth
// there, and it has no power switch of the rig's.
TEST(SimulatedSource, TheCheckCameraSeesThePyramidBase) {
  const auto museum = smallMuseum();
  SimulatedSource check(museum, sim::Museum::kCheckCamera, SimulationOptions{.paced = false});
  EXPECT_EQ(check.name().substr(check.name().size() - 6), "/check");
  check.open();
  check.start();
  const GrabResult grabbed = check.grab(30s);
  ASSERT_EQ(grabbed.status, GrabStatus::Ok);
  const CameraModel& model = museum->camera(sim::Museum::kCheckCamera);
  float true_depth = 0.0f;
  const std::optional<vec2> base_centre = model.project(vec3(0.0f), &true_depth);
  ASSERT_TRUE(base_centre.has_value());
  const int x = static_cast<int>(std::lround(base_centre->x)),
            y = static_cast<int>(std::lround(base_centre->y));
  ASSERT_TRUE(x >= 0 && y >= 0 && x < model.width() && y < model.height());
  EXPECT_NEAR(grabbed.frame.depth.at<float>(y, x), true_depth, 0.03f) << "the base top at the relic's place";
}

TEST(SimulatedSource, RunsInACaptureThreadAndRejectsBadCameras) {
  const auto museum = smallMuseum();
  EXPECT_THROW(SimulatedSource(museum, 5), InputError);
  EXPECT_THROW(SimulatedSource(museum, -1), InputError);
  LatestFrameMailbox mailbox;
  CaptureOptions options;
  options.camera_id = 3;
  CaptureThread thread(
      std::make_unique<SimulatedSource>(museum, 3, SimulationOptions{.paced = true, .frame_count = 4}),
      mailbox, options);
  const auto frame = mailbox.waitAndTake(30s);
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(frame->camera_id, 3);
  const auto end = Clock::now() + 30s;
  while (!thread.finished() && Clock::now() < end) std::this_thread::sleep_for(10ms);
  EXPECT_TRUE(thread.finished());
  EXPECT_EQ(thread.health().frames_completed, 4);
}

TEST(SimulatedSource, BuildsTheConfiguredSimCameras) {
  const CaptureConfig c = parseCaptureConfig(ConfigNode::parse(R"(
capture:
  cameras:
    - {face: 0, backend: sim, scene: room, paced: false}
    - {face: 1, backend: sim, scene: room, camera: 3}
)",
                                                               "holo.yaml")["capture"]);
  const auto sources = makeSources(c, configuredSources());
  ASSERT_EQ(sources.size(), 2u);
  EXPECT_EQ(sources[0]->name(), "sim:room/cam0");
  EXPECT_EQ(sources[1]->name(), "sim:room/cam3");
  EXPECT_TRUE(sources[1]->cameraModel().has_value());
}
