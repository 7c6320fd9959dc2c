// The live frame loop run in-process on the simulated museum: frames come out with the relic on
// them, the same inputs give the same images, and a camera whose stream ends leaves the
// foreground while the others go on. Small views (48 pixels) and a small panorama keep it quick.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "holo/capture/simulated_source.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/pipeline/installation.hpp"
#include "holo/sim/museum.hpp"

namespace holo::pipeline {
namespace {

constexpr int kViewSize = 48;
constexpr int kPanoramaWidth = 128;

FrameLoopOptions smallOptions() {
  FrameLoopOptions options;
  options.view_size = kViewSize;
  options.panorama_width = kPanoramaWidth;
  return options;
}

std::vector<cv::Mat> displayedViews(const FrameLoop& loop) {
  std::vector<cv::Mat> views;
  for (const reflect::ViewImages& view : loop.lastResult().views) views.push_back(view.display.clone());
  return views;
}

TEST(FrameLoop, RendersFramesOfTheSimulatedMuseumWithTheRelicOnThem) {
  FrameLoop loop(smallOptions(), nullptr);
  EXPECT_EQ(loop.cameras().size(), 4u);
  for (int i = 0; i < 3; ++i) {
    const FrameReport report = loop.step();
    EXPECT_EQ(report.index, i);
    EXPECT_FALSE(report.cameras_ended);
    EXPECT_EQ(report.cameras_live, 4);
    EXPECT_EQ(report.non_finite_pixels, 0);
    EXPECT_GT(report.relic_pixels, 0u);
    EXPECT_GT(report.times.total, 0.0);
  }
  const std::vector<cv::Mat> views = displayedViews(loop);
  ASSERT_EQ(views.size(), 4u);
  for (const cv::Mat& view : views) {
    ASSERT_EQ(view.size(), cv::Size(kViewSize, kViewSize));
    ASSERT_EQ(view.type(), CV_8UC3);
    cv::Mat grey;
    cv::extractChannel(view, grey, 1);
    // The relic fills part of each view, lit; around it the view is black.
    const double lit = double(cv::countNonZero(grey > 8)) / double(grey.total());
    EXPECT_GT(lit, 0.05);
    EXPECT_LT(lit, 0.95);
  }
  const CameraFrameCounts counts = loop.cameraFrameCounts();
  EXPECT_TRUE(counts.simulated);  // during the run: no preloading
  EXPECT_EQ(counts.consumed, 4 * 3);
}

TEST(FrameLoop, TheSameInputsGiveTheSameImages) {
  std::vector<std::vector<cv::Mat>> runs;
  for (int run = 0; run < 2; ++run) {
    FrameLoop loop(smallOptions(), nullptr);
    loop.step();
    loop.step();
    runs.push_back(displayedViews(loop));
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  for (std::size_t v = 0; v < runs[0].size(); ++v)
    EXPECT_EQ(cv::norm(runs[0][v], runs[1][v], cv::NORM_L1), 0.0) << "view " << v;
}

TEST(FrameLoop, ACameraWhoseStreamEndsIsDroppedAndTheOthersGoOn) {
  const FrameLoopOptions options = smallOptions();
  Installation installation = simulatedInstallation(options.scene, /*paced=*/false, options.panorama_width);
  // Camera 3 delivers two frames, then reports the end of its stream, as a recording that ended.
  auto museum = std::make_shared<const sim::Museum>(sim::loadScene(options.scene));
  installation.sources[3] = std::make_unique<capture::SimulatedSource>(
      museum, 3, capture::SimulationOptions{.paced = false, .frame_count = 2});
  FrameLoop loop(options, std::move(installation), nullptr);
  std::vector<int> live;
  for (int i = 0; i < 4; ++i) {
    const FrameReport report = loop.step();
    ASSERT_FALSE(report.cameras_ended);  // the other three go on
    EXPECT_GT(report.relic_pixels, 0u);
    live.push_back(report.cameras_live);
  }
  EXPECT_EQ(live, (std::vector<int>{4, 4, 3, 3}));
}

// With simulated cameras, the table keeps their rendering apart from the appliance's stages and
// gives the appliance's own frame rate beside the whole frame's, with the command that measures
// it properly.
TEST(TimingTable, SeparatesSimulatingTheCamerasFromTheApplianceStages) {
  FrameReport report;
  report.times = {.acquisition = 160,
                  .foreground = 10,
                  .dynamic = 8,
                  .statics = 6,
                  .composition = 4,
                  .display = 2,
                  .total = 200,
                  .pipeline_wait = 170};
  const std::vector<FrameReport> reports = {report};
  CameraFrameCounts cameras;
  cameras.simulated = true;
  const StageTimes median = medianTimes(reports);
  EXPECT_DOUBLE_EQ(median.applianceStages(), 30.0);
  const std::string table = formatTimingTable(median, reports, cameras);
  const std::size_t appliance = table.find("appliance stages, one after another     30.00");
  const std::size_t own_fps = table.find("  frames per second, no overlap        33.33");
  const std::size_t simulation = table.find("simulating the cameras (no real installation pays this)");
  const std::size_t acquisition = table.find("  acquisition (wait)                  160.00");
  const std::size_t whole_fps = table.find("  frames per second                     5.00");
  ASSERT_NE(appliance, std::string::npos) << table;
  ASSERT_NE(own_fps, std::string::npos) << table;
  ASSERT_NE(simulation, std::string::npos) << table;
  ASSERT_NE(acquisition, std::string::npos) << table;
  ASSERT_NE(whole_fps, std::string::npos) << table;
  EXPECT_LT(appliance, simulation);
  EXPECT_LT(simulation, acquisition);
  EXPECT_NE(table.find("holopyramid bench frame"), std::string::npos) << table;
  const std::string json = timingJson(median, reports, cameras);
  EXPECT_NE(json.find("\"appliance_fps\": 33.3"), std::string::npos) << json;
  EXPECT_NE(json.find("\"simulated_cameras\": true"), std::string::npos) << json;

  // Real cameras: waiting for them is the appliance's own acquisition stage.
  cameras.simulated = false;
  const std::string real = formatTimingTable(median, reports, cameras);
  EXPECT_EQ(real.find("simulating the cameras"), std::string::npos) << real;
  EXPECT_LT(real.find("acquisition (wait)"), real.find("foreground point cloud")) << real;
}

}  // namespace
}  // namespace holo::pipeline
