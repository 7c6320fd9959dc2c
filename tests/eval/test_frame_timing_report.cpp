// The frame loop's timing report (eval/frame_timing_report.hpp) on a hand-made frame report: the
// table and its JSON keep the simulated cameras' rendering apart from the appliance's stages.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "holo/eval/frame_timing_report.hpp"

namespace holo::eval {
namespace {

using pipeline::CameraFrameCounts;
using pipeline::FrameReport;
using pipeline::StageTimes;

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
}  // namespace holo::eval
