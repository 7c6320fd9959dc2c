#include "holo/capture/recorder.hpp"

#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/log.hpp"
#include "holo/core/stats.hpp"

namespace holo::capture {

namespace fs = std::filesystem;

namespace {

std::string cameraFolder(std::size_t index) {
  return "cam" + std::to_string(index);
}

std::string frameName(std::size_t number) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%06zu.png", number);
  return buffer;
}

std::string timestampText(double t) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6f", t);
  return buffer;
}

void writePng(const fs::path& path, const cv::Mat& image) {
  writeAtomically(path, [&](const fs::path& tmp) {
    if (!cv::imwrite(tmp.string(), image)) throw Error("could not write " + path.string());
  });
}

// YAML scalars written by us: names are quoted so any character survives.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

Recorder::Recorder(fs::path root, std::vector<RecorderCamera> cameras, double depth_scale, int index_every)
    : root_(std::move(root)),
      cameras_(std::move(cameras)),
      depth_scale_(depth_scale),
      index_every_(index_every),
      entries_(cameras_.size()) {
  if (!(depth_scale_ > 0)) throw InputError(root_.string(), "depth_scale", "a positive number");
  if (fs::exists(root_ / kRecordingFile))
    throw InputError(root_.string(), "", "a folder without a recording (never overwrite one)",
                     "it already holds " + std::string(kRecordingFile));
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    fs::create_directories(root_ / cameraFolder(i) / "rgb");
    fs::create_directories(root_ / cameraFolder(i) / "depth");
  }
}

Recorder::~Recorder() {
  try {
    finish();
  } catch (const std::exception& e) {
    HOLO_LOG_ERROR("recorder {}: could not finish: {}", root_.string(), e.what());
  }
}

void Recorder::write(const RgbdFrame& frame, std::optional<Nanoseconds> depth_time) {
  frame.validate();
  if (frame.camera_id >= static_cast<int>(cameras_.size()))
    throw Error("recorder: frame of camera " + std::to_string(frame.camera_id) + " but only " +
                std::to_string(cameras_.size()) + " cameras configured");
  const auto cam = static_cast<std::size_t>(frame.camera_id);
  const fs::path dir = root_ / cameraFolder(cam);
  auto& list = entries_[cam];
  const std::string file = frameName(list.size());

  double t = 0;
  if (frame.device_time.count() != 0) {
    t = std::chrono::duration<double>(frame.device_time).count();
  } else {
    if (!first_host_time_) first_host_time_ = frame.host_time;
    t = std::chrono::duration<double>(frame.host_time - *first_host_time_).count();
  }
  const double t_depth = depth_time ? std::chrono::duration<double>(*depth_time).count() : t;
  Entry entry{t, t_depth, "", ""};
  if (!frame.colour.empty()) {
    entry.colour = "rgb/" + file;
    writePng(dir / entry.colour, frame.colour);
  }
  if (!frame.depth.empty()) {
    entry.depth = "depth/" + file;
    std::int64_t clipped = 0;
    writePng(dir / entry.depth, depthToU16(frame.depth, depth_scale_, &clipped));
    if (clipped > 0) {
      static auto& counter = stats::counter("Capture/Depth pixels beyond the 16-bit recording range");
      counter.fetch_add(clipped, std::memory_order_relaxed);
      depth_clipped_ += clipped;
    }
  }
  list.push_back(std::move(entry));
  ++frames_written_;
  finished_ = false;
  if (index_every_ > 0 && frames_written_ % index_every_ == 0) writeIndices();
}

void Recorder::finish() {
  if (finished_) return;
  writeIndices();
  finished_ = true;
}

void Recorder::writeIndices() const {
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    std::ostringstream rgb, depth, assoc;
    rgb << "# colour images\n# file: " << cameras_[i].name << "\n# timestamp filename\n";
    depth << "# depth images (16-bit PNG, " << depth_scale_
          << " units per metre, 0 = invalid)\n# file: " << cameras_[i].name << "\n# timestamp filename\n";
    assoc << "# timestamp rgb_file timestamp depth_file\n";
    for (const Entry& e : entries_[i]) {
      const std::string t = timestampText(e.t);
      if (!e.colour.empty()) rgb << t << ' ' << e.colour << '\n';
      const std::string t_depth = timestampText(e.t_depth);
      if (!e.depth.empty()) depth << t_depth << ' ' << e.depth << '\n';
      if (!e.colour.empty() && !e.depth.empty())
        assoc << t << ' ' << e.colour << ' ' << t_depth << ' ' << e.depth << '\n';
    }
    const fs::path dir = root_ / cameraFolder(i);
    writeFileAtomically(dir / "rgb.txt", rgb.str());
    writeFileAtomically(dir / "depth.txt", depth.str());
    writeFileAtomically(dir / "associations.txt", assoc.str());
  }

  std::ostringstream yaml;
  yaml.precision(9);
  yaml << "# Holopyramid recording: one TUM RGB-D style folder per camera (see capture/recording.hpp)\n"
       << "format: holopyramid-recording\nversion: 1\n"
       << "depth_scale: " << depth_scale_ << "  # depth PNG units per metre\ncameras:\n";
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    const RecorderCamera& c = cameras_[i];
    yaml << "  - id: " << i << "\n    name: " << quoted(c.name) << "\n    serial: " << quoted(c.serial)
         << "\n    folder: " << cameraFolder(i) << "\n    frames: " << entries_[i].size() << "\n";
    if (c.model) {
      const Intrinsics& K = c.model->intrinsics();
      yaml << "    intrinsics: {width: " << K.width << ", height: " << K.height << ", fx: " << K.fx
           << ", fy: " << K.fy << ", cx: " << K.cx << ", cy: " << K.cy << ", distortion: [";
      for (std::size_t k = 0; k < 5; ++k) yaml << (k ? ", " : "") << K.distortion[k];
      yaml << "]}\n    T_world_camera: [";
      const mat4& T = c.model->T_world_camera();
      for (int r = 0; r < 4; ++r)
        for (int col = 0; col < 4; ++col) yaml << (r || col ? ", " : "") << T[col][r];
      yaml << "]  # row-major, camera to world, metres\n";
    }
  }
  writeFileAtomically(root_ / kRecordingFile, yaml.str());
}

}  // namespace holo::capture
