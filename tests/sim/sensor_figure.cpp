// `build/tests/sim/sensor_figure OUT.png [SHARED_DATA]`: the figure and the table of docs/sim.md,
// "Sensor profiles". Renders frame 5 of the museum under each sensor profile (the camera that sees
// the most visitor pixels), puts their depth beside the real Kinect frame with two people (TUM
// fr3/walking_xyz, when SHARED_DATA or ../shared/data has it) on one colour scale, and prints the
// statistics of each (holo/sim/depth_statistics.hpp), the simulated ones pooled over the four
// cameras.
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "holo/sim/depth_statistics.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/person_segmentation.hpp"
#include "tum_walking.hpp"

namespace {

constexpr float kFarthest = 6.0f;  // metres at the cold end of the colour scale
constexpr int kPanelHeight = 300;

cv::Mat panel(const cv::Mat& depth, const std::string& label) {
  cv::Mat scaled, colour;
  depth.convertTo(scaled, CV_8U, -255.0 / kFarthest, 255.0);
  cv::applyColorMap(scaled, colour, cv::COLORMAP_TURBO);
  colour.setTo(cv::Scalar::all(0), depth <= 0.0f);
  cv::resize(colour, colour, {depth.cols * kPanelHeight / depth.rows, kPanelHeight}, 0, 0, cv::INTER_NEAREST);
  cv::putText(colour, label, {8, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(colour, label, {8, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
  return colour;
}

cv::Mat row(const cv::Mat& left, const cv::Mat& right, int width) {
  cv::Mat out = cv::Mat::zeros(kPanelHeight, width, CV_8UC3);
  left.copyTo(out(cv::Rect(0, 0, left.cols, left.rows)));
  right.copyTo(out(cv::Rect(width - right.cols, 0, right.cols, right.rows)));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace holo::sim;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s OUT.png [SHARED_DATA]\n", argv[0]);
    return 2;
  }
  const std::filesystem::path shared =
      argc > 2 ? std::filesystem::path(argv[2])
               : std::filesystem::path(HOLO_SOURCE_DIR).parent_path() / "shared" / "data";
  const auto real_path = shared / "rgbd" / "tum_walking" / "depth.png";
  cv::Mat real = cv::Mat::zeros(480, 640, CV_32FC1);
  if (std::filesystem::exists(real_path)) {
    real = loadDepthPng(real_path.string(), holo::test::kTumDepthUnitsPerMetre);
    const cv::Mat people =
        segmentPeople(real, holo::test::tumFr3Intrinsics(), holo::test::tumWalkingPersonSeeds());
    std::printf("real Kinect, TUM fr3/walking_xyz (640x480), people by segmentPeople:\n%s\n\n",
                describe(measureDepthStatistics(real, people)).c_str());
    // The people mask over the colour frame, for docs/sim.md ("People in a real frame").
    cv::Mat colour = cv::imread((real_path.parent_path() / "color.png").string(), cv::IMREAD_COLOR);
    if (!colour.empty()) {
      cv::Mat tint = colour.clone();
      tint.setTo(cv::Scalar(255, 0, 255), people);
      cv::addWeighted(colour, 0.5, tint, 0.5, 0.0, colour);
      const auto people_path = std::filesystem::path(argv[1]).parent_path() / "tum_walking_people.png";
      if (cv::imwrite(people_path.string(), colour)) std::printf("wrote %s\n", people_path.string().c_str());
    }
  }
  constexpr int kFrame = 5;
  std::vector<cv::Mat> panels;
  for (const SensorProfile profile :
       {SensorProfile::structured_light, SensorProfile::uniform, SensorProfile::stereo}) {
    SceneDescription scene = loadScene("museum");
    scene.noise = sensorProfile(profile);
    const Museum museum(scene);
    std::vector<cv::Mat> depths, people;
    int shown = 0;
    double in_both = 0, in_either = 0;
    std::vector<cv::Mat> grown;
    for (int camera = 0; camera < museum.cameraCount(); ++camera) {
      const SimulatedFrame f = museum.renderCamera(camera, kFrame);
      depths.push_back(f.frame.depth);
      people.push_back(f.foreground);
      const auto seeds = seedsFromMask(f.foreground, f.frame.depth, museum.camera(camera).intrinsics());
      grown.push_back(seeds.empty()
                          ? cv::Mat()
                          : segmentPeople(f.frame.depth, museum.camera(camera).intrinsics(), seeds));
      if (cv::countNonZero(f.foreground) > cv::countNonZero(people[static_cast<std::size_t>(shown)]))
        shown = camera;
      // Flicker: the holes off the visitors of both frames, where the hall stands still.
      const SimulatedFrame next = museum.renderCamera(camera, kFrame + 1);
      const cv::Mat hall = (f.foreground == 0) & (next.foreground == 0);
      const cv::Mat a = (f.frame.depth == 0.0f) & hall, b = (next.frame.depth == 0.0f) & hall;
      in_both += cv::countNonZero(a & b);
      in_either += cv::countNonZero(a | b);
    }
    std::printf(
        "simulated museum, %s, frame %d, 4 cameras 640x360:\n%s\nhall holes in both frames %d and %d / in "
        "either: %.1f%%\n\n",
        sensorProfileName(profile), kFrame, describe(measureDepthStatistics(depths, people)).c_str(), kFrame,
        kFrame + 1, 100.0 * in_both / in_either);
    const DepthStatistics by_segmentation = measureDepthStatistics(depths, grown);
    std::printf("people by segmentPeople as on the real frame: holes on people %.2f%%, elsewhere %.1f%%\n\n",
                100.0 * by_segmentation.person_hole_fraction, 100.0 * by_segmentation.other_hole_fraction);
    panels.push_back(
        panel(depths[static_cast<std::size_t>(shown)],
              std::string("simulated, ") + sensorProfileName(profile) + ", cam" + std::to_string(shown)));
  }
  const cv::Mat real_panel = panel(real, "real Kinect, TUM walking_xyz");
  const int width = real_panel.cols + panels[0].cols + 8;
  cv::Mat figure;
  cv::vconcat(std::vector<cv::Mat>{row(real_panel, panels[0], width), cv::Mat::zeros(8, width, CV_8UC3),
                                   row(panels[1], panels[2], width)},
              figure);
  if (!cv::imwrite(argv[1], figure)) {
    std::fprintf(stderr, "could not write %s\n", argv[1]);
    return 1;
  }
  std::printf("wrote %s (depth 0-%.0f m, warm = near, black = no depth)\n", argv[1], kFarthest);
  return 0;
}
