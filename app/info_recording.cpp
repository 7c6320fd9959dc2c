#include "info_recording.hpp"

#include <opencv2/core.hpp>
#include <ostream>

#include "holo/capture/recording.hpp"
#include "holo/capture/recording_source.hpp"

namespace holo::app {

int describeRecording(const std::filesystem::path& folder, std::ostream& out) {
  const capture::Recording recording = capture::readRecording(folder);
  out << "folder: " << recording.root.string() << "\n"
      << "type: recording (" << recording.layout << ")\n"
      << "cameras: " << recording.cameras.size() << "\n";
  for (const auto& camera : recording.cameras) {
    const auto& frames = camera.frames;
    const double duration = frames.size() > 1 ? frames.back().timestamp_s - frames.front().timestamp_s : 0.0;
    out << "camera " << camera.id << ": " << camera.name << "\n"
        << "  serial: " << (camera.serial.empty() ? "-" : camera.serial) << "\n"
        << "  frames: " << frames.size() << "\n"
        << "  duration s: " << duration << "\n";
    if (duration > 0) out << "  rate hz: " << static_cast<double>(frames.size() - 1) / duration << "\n";
    out << "  depth scale (units per metre): " << camera.depth_scale << "\n";
    if (camera.model) {
      const Intrinsics& K = camera.model->intrinsics();
      out << "  intrinsics: " << K.width << "x" << K.height << " fx " << K.fx << " fy " << K.fy << " cx "
          << K.cx << " cy " << K.cy << "\n";
      const vec3 position(camera.model->T_world_camera()[3]);
      out << "  position m: " << position.x << " " << position.y << " " << position.z << "\n";
    } else {
      out << "  intrinsics: unknown\n";
    }
    if (frames.empty()) continue;
    // The first frame tells whether the files are what the index says (and how much depth there is).
    const RgbdFrame first = capture::RecordingSource(camera).load(0);
    if (!first.color.empty()) out << "  colour: " << first.color.cols << "x" << first.color.rows << "\n";
    if (!first.depth.empty()) {
      const cv::Mat valid = first.depth > 0;
      double lo = 0, hi = 0;
      cv::minMaxLoc(first.depth, &lo, &hi, nullptr, nullptr, valid);
      out << "  depth: " << first.depth.cols << "x" << first.depth.rows << ", valid "
          << 100.0 * cv::countNonZero(valid) / static_cast<double>(first.depth.total()) << "%, range m " << lo
          << " - " << hi << "\n";
    }
  }
  return 0;
}

}  // namespace holo::app
