// `build/tests/sim/visitors_figure OUT.jpg [SHARED_DATA]`: the figure of docs/sim.md, "Visitors":
// a simulated camera frame of the default museum with the bodies visitor model next to the real Kinect frame
// with two people (TUM fr3/walking_xyz, when SHARED_DATA or ../shared/data has it), colour above, depth below
// on one colour scale. The simulated frame is the camera and frame (of the first 20 s, every 0.5 s) that
// shows the most visitor pixels with every head in view (no visitor pixel in the top row).
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "holo/sim/depth_statistics.hpp"
#include "holo/sim/museum.hpp"
#include "tum_walking.hpp"

namespace {

constexpr float kFarthest = 6.0f;  // metres at the cold end of the depth colour scale
constexpr int kPanelHeight = 300;

cv::Mat labelled(cv::Mat image, const std::string& label) {
  cv::resize(image, image, {image.cols * kPanelHeight / image.rows, kPanelHeight}, 0, 0, cv::INTER_AREA);
  cv::putText(image, label, {8, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(image, label, {8, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
  return image;
}

cv::Mat depthColours(const cv::Mat& depth) {
  cv::Mat scaled, colour;
  depth.convertTo(scaled, CV_8U, -255.0 / kFarthest, 255.0);
  cv::applyColorMap(scaled, colour, cv::COLORMAP_TURBO);
  colour.setTo(cv::Scalar::all(0), depth <= 0.0f);
  return colour;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace holo::sim;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s OUT.jpg [SHARED_DATA]\n", argv[0]);
    return 2;
  }
  const std::filesystem::path shared =
      argc > 2 ? std::filesystem::path(argv[2])
               : std::filesystem::path(HOLO_SOURCE_DIR).parent_path() / "shared" / "data";
  const auto tum = shared / "rgbd" / "tum_walking";
  cv::Mat real_colour = cv::imread((tum / "color.png").string(), cv::IMREAD_COLOR);
  cv::Mat real_depth = std::filesystem::exists(tum / "depth.png")
                           ? loadDepthPng((tum / "depth.png").string(), holo::test::kTumDepthUnitsPerMetre)
                           : cv::Mat();
  if (real_colour.empty() || real_depth.empty()) {
    std::fprintf(stderr, "no real frame in %s\n", tum.string().c_str());
    return 1;
  }

  // The search on small noiseless frames, then the pick at full size with the scene's sensor.
  SceneDescription scene = loadScene("museum");
  scene.visitor_model = VisitorModel::bodies;
  SceneDescription small = scene;
  small.camera.width = 160;
  small.camera.height = 90;
  small.noise.enabled = false;
  const Museum search(small);
  int best_frame = 0, best_camera = 0, best_pixels = -1;
  for (int frame = 0; frame < 600; frame += 15)
    for (int c = 0; c < search.cameraCount(); ++c) {
      const cv::Mat mask = search.renderCamera(c, frame).foreground;
      if (cv::countNonZero(mask.row(0)) > 0) continue;
      const int pixels = cv::countNonZero(mask);
      if (pixels > best_pixels) best_pixels = pixels, best_frame = frame, best_camera = c;
    }
  const Museum museum(scene);
  const SimulatedFrame f = museum.renderCamera(best_camera, best_frame);
  std::printf("simulated: museum, camera %d, frame %d (%.1f s), %dx%d\n", best_camera, best_frame,
              museum.frameTime(best_frame), f.frame.colour.cols, f.frame.colour.rows);

  const std::vector<cv::Mat> top = {labelled(real_colour, "real Kinect, TUM walking_xyz"),
                                    labelled(f.frame.colour, "simulated museum camera")};
  const std::vector<cv::Mat> bottom = {
      labelled(depthColours(real_depth), "real depth (0-6 m)"),
      labelled(depthColours(f.frame.depth), "simulated depth, structured-light")};
  cv::Mat a, b, figure;
  cv::hconcat(top, a);
  cv::hconcat(bottom, b);
  cv::vconcat(a, b, figure);
  if (!cv::imwrite(argv[1], figure, {cv::IMWRITE_JPEG_QUALITY, 85})) {
    std::fprintf(stderr, "could not write %s\n", argv[1]);
    return 1;
  }
  std::printf("wrote %s\n", argv[1]);
  return 0;
}
