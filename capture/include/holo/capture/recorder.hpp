// Writes a recording (layout in recording.hpp) frame by frame. Every file goes through
// holo::writeAtomically, and the index files and recording.yaml are rewritten (atomically) every
// `index_every` frames and at finish(), so a crash loses at most the index lines of the last few
// frames and never leaves a half-written file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "holo/capture/recording.hpp"
#include "holo/core/rgbd_frame.hpp"

namespace holo::capture {

struct RecorderCamera {
  std::string name;
  std::string serial;
  std::optional<CameraModel> model;
};

class Recorder {
 public:
  // Creates `root` (which must not hold another recording already: throws InputError).
  Recorder(std::filesystem::path root, std::vector<RecorderCamera> cameras,
           double depth_scale = kDefaultDepthScale, int index_every = 30);
  ~Recorder();  // finish(), logging instead of throwing
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Writes the frame of camera frame.camera_id (0-based index into `cameras`). The timestamp is
  // frame.device_time when set, else host_time relative to the first frame written; the depth
  // image's is `depth_time` when given (a second device's clock), else the same.
  void write(const RgbdFrame& frame, std::optional<Nanoseconds> depth_time = std::nullopt);
  // Writes the indices and recording.yaml; idempotent.
  void finish();

  std::int64_t framesWritten() const { return frames_written_; }
  // Depth pixels that did not fit the 16-bit range and were stored as 0.
  std::int64_t depthClipped() const { return depth_clipped_; }
  const std::filesystem::path& root() const { return root_; }

 private:
  struct Entry {
    double t;
    double t_depth;
    std::string colour;  // relative to the camera folder, "" when none
    std::string depth;
  };
  void writeIndices() const;

  std::filesystem::path root_;
  std::vector<RecorderCamera> cameras_;
  double depth_scale_;
  int index_every_;
  std::vector<std::vector<Entry>> entries_;
  std::optional<Clock::time_point> first_host_time_;
  std::int64_t frames_written_ = 0;
  std::int64_t depth_clipped_ = 0;
  bool finished_ = false;
};

}  // namespace holo::capture
