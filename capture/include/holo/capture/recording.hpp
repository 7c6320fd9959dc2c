// Recorded RGB-D sequences on disk, TUM RGB-D style, and how to read them.
//
// Layout written by holo::capture::Recorder (one folder per camera, each a TUM sequence):
//   DIR/recording.yaml        format, depth_scale (PNG units per metre), and per camera its id,
//                             name, serial, folder, intrinsics and T_world_camera (row-major)
//   DIR/cam0/rgb/000000.png   colour, 8-bit BGR PNG (bit-exact)
//   DIR/cam0/depth/000000.png depth, 16-bit PNG: metres * depth_scale, 0 = no measurement
//   DIR/cam0/rgb.txt, depth.txt   "timestamp file" per line (seconds), '#' comments (TUM format)
//   DIR/cam0/associations.txt     "t_rgb rgb/x.png t_depth depth/x.png" per frame (the two times
//                                 differ for a camera whose colour and depth are two devices)
//
// readRecording() also reads
//   * a plain TUM sequence folder (rgb.txt + depth.txt, associations.txt optional; depth scale
//     5000 as TUM publishes), and
//   * a single-frame folder (colour.png or rgb.png + depth.png, depth scale 5000, intrinsics from an
//     Open3D-style *.json with width, height and a column-major intrinsic_matrix), such as
//     ../shared/data/rgbd/tum.
#pragma once

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "holo/core/camera_model.hpp"

namespace holo::capture {

inline constexpr double kTumDepthScale = 5000.0;      // TUM RGB-D: 5000 units per metre
inline constexpr double kDefaultDepthScale = 1000.0;  // ours: millimetres, up to 65.5 m
inline constexpr const char* kRecordingFile = "recording.yaml";

struct RecordedFrame {
  double timestamp_s = 0;        // seconds, source-defined epoch (the colour image's)
  std::filesystem::path colour;  // absolute; empty when the frame has no colour
  std::filesystem::path depth;   // absolute; empty when the frame has no depth
  // The depth image's own time: colour and depth from two devices are paired within a tolerance
  // (associations.txt), not taken at one instant.
  double depth_timestamp_s = 0;
};

struct RecordedCamera {
  int id = 0;
  std::string name;
  std::string serial;
  std::optional<CameraModel> model;  // intrinsics and pose when the recording has them
  double depth_scale = kDefaultDepthScale;
  std::vector<RecordedFrame> frames;  // in time order
};

struct Recording {
  std::filesystem::path root;
  std::string layout;  // "holopyramid", "tum-sequence" or "single-frame"
  std::vector<RecordedCamera> cameras;
};

// True when `folder` has one of the layouts above.
bool isRecordingFolder(const std::filesystem::path& folder);
// Index files (rgb.txt, depth.txt, associations.txt) larger than this are refused: about a
// million frames, whose index then takes ~200 MB. A 100k-frame recording (an hour at 30 fps)
// reads in well under a second and holds ~20 MB of index per camera; frames load one at a time.
inline constexpr std::uintmax_t kMaxRecordingIndexBytes = std::uintmax_t{64} << 20;

// Throws InputError naming the file and field for anything missing or malformed.
Recording readRecording(const std::filesystem::path& folder);

// 16-bit depth PNG pixels <-> metres. Values that do not fit (beyond 65535 / scale, NaN, Inf,
// negative) become 0 = invalid; `clipped` (optional) counts the ones that were finite and > 0.
cv::Mat depthToU16(const cv::Mat& depth_m, double depth_scale, std::int64_t* clipped = nullptr);
cv::Mat depthFromU16(const cv::Mat& depth_u16, double depth_scale);

}  // namespace holo::capture
