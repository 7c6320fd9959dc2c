// A kiosk with the console on and a small frame source of its own, for the browser test
// (test_console_browser.py): four faces and four cameras whose pictures change every frame, an
// exhibit of three relics that NextRelic steps through, plausible camera health. No renderer,
// no cameras, no playlist: the test checks the console, not the pipeline.
//
//   console_demo SECRET_FILE PORT_FILE   serves on 127.0.0.1 (a free port, written to PORT_FILE)
//                                        until SIGTERM
#include <array>
#include <fstream>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <string>

#include "holo/core/config.hpp"
#include "holo/core/log.hpp"
#include "holo/kiosk/kiosk_loop.hpp"

namespace {

using namespace holo::kiosk;

const std::array<std::string, 3> kRelics = {"Amphora of Knossos", "Bronze helmet", "Gold mask of Agamemnon"};

cv::Mat face(int f, std::int64_t frame, const std::string& relic) {
  cv::Mat image(240, 240, CV_8UC3, cv::Scalar(40 + 50 * f, 30, 90));
  const double angle = static_cast<double>(frame) * 0.15 + f * 1.57;
  const cv::Point centre(120 + static_cast<int>(70 * std::cos(angle)),
                         120 + static_cast<int>(70 * std::sin(angle)));
  cv::circle(image, centre, 28, cv::Scalar(60, 200, 240), cv::FILLED, cv::LINE_AA);
  cv::putText(image, "face " + std::to_string(f), {10, 28}, cv::FONT_HERSHEY_SIMPLEX, 0.8,
              cv::Scalar(255, 255, 255), 2);
  cv::putText(image, relic.substr(0, 18), {10, 225}, cv::FONT_HERSHEY_SIMPLEX, 0.55,
              cv::Scalar(255, 255, 255), 1);
  return image;
}

cv::Mat camera(int c, std::int64_t frame) {
  cv::Mat image(240, 320, CV_8UC3, cv::Scalar(70, 75, 80));
  cv::rectangle(image, {0, 170}, {320, 240}, cv::Scalar(110, 115, 120), cv::FILLED);
  const int x = static_cast<int>((frame * 4 + c * 80) % 360) - 20;
  cv::ellipse(image, {x, 130}, {16, 50}, 0, 0, 360, cv::Scalar(40, 60, 150), cv::FILLED, cv::LINE_AA);
  cv::putText(image, "camera " + std::to_string(c) + "  frame " + std::to_string(frame), {8, 22},
              cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(255, 255, 255), 1);
  return image;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: console_demo SECRET_FILE PORT_FILE\n";
    return 2;
  }
  SignalEvents signals;  // before any thread starts, so all inherit the signal mask
  SystemdNotifier notifier;
  LoadedConfig config{
      holo::ConfigNode::parse(factoryDefaultsYaml(), "factory defaults"), {}, "console demo", {}};
  config.kiosk = parseKioskConfig(config.root);
  config.kiosk.health_port = -1;
  config.kiosk.health_file.clear();
  config.kiosk.console.enabled = true;
  config.kiosk.console.port = 0;
  config.kiosk.console.secret_file = argv[1];

  std::size_t relic = 0;
  std::array<std::int64_t, 4> camera_frames{};
  KioskLoop loop(
      config,
      [&](const FrameRequest& request) {
        for (const KioskAction action : request.actions) {
          if (action == KioskAction::NextRelic) relic = (relic + 1) % kRelics.size();
          HOLO_LOG_INFO("demo frame source: {}", kioskActionName(action));
        }
        FrameReport report;
        report.presented = true;
        report.relic = kRelics[relic];
        report.next_relic = kRelics[(relic + 1) % kRelics.size()];
        report.stage_ms = {
            {"acquisition", 2.1}, {"foreground", 9.8}, {"composition", 14.2}, {"display", 1.3}};
        report.foreground_share = 0.08;
        report.camera_skew_ms = 3.4;
        for (int c = 0; c < 4; ++c) {
          CameraHealth health;
          health.name = "camera " + std::to_string(c);
          health.alive = true;
          health.frames = ++camera_frames[static_cast<std::size_t>(c)];
          health.last_frame_age_s = 0.02;
          health.pair_skew_ms = 1.5 + c;
          report.cameras.push_back(health);
        }
        if (request.snapshot) {
          report.snapshot.emplace();
          for (int f = 0; f < 4; ++f)
            report.snapshot->faces[static_cast<std::size_t>(f)] = face(f, request.index, kRelics[relic]);
          for (int c = 0; c < 4; ++c) report.snapshot->cameras.push_back(camera(c, request.index));
        }
        return report;
      },
      [&] { return config; });
  if (loop.consolePort() == 0) {
    std::cerr << "console_demo: the console did not start (see the log above)\n";
    return 1;
  }
  std::ofstream(argv[2]) << loop.consolePort() << "\n";
  return loop.run(signals, notifier);
}
