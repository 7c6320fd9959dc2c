// The `capture:` section of the project's YAML configuration: which camera is which pyramid
// face, through which backend, with which formats and depth scales. Example:
//
//   capture:
//     calibration_dir: calibration        # camera_SERIAL.yml files (calib module)
//     grab_timeout_ms: 200                # capture thread settings, all optional
//     silence_timeout_ms: 2000
//     max_backoff_ms: 5000
//     pair_tolerance_ms: 16               # colour and depth from two devices: frames further apart
//                                         # (arrival time; a recording's own times) are dropped,
//                                         # counted (frame_pairing.hpp)
//     cameras:
//       - face: 0                         # 0..3: the side facing +Z, +X, -Z, -X
//         backend: aravis                 # aravis | v4l2 | recording
//         colour: {serial: "GV-0001", pixel_format: BayerRG8, width: 640, height: 360, frame_rate: 30}
//         depth: {serial: "GV-0002", pixel_format: Coord3D_C16, depth_scale: 0.001}
//       - face: 1
//         backend: v4l2
//         colour: {device: "serial:843112071234", pixel_format: YUYV, width: 640, height: 480}
//         depth: {device: "serial:843112071234-depth", pixel_format: Z16, depth_scale: 0.001}
//       - face: 2
//         backend: recording
//         path: recordings/hall-monday    # a recording folder (recording.hpp)
//         camera: 2                       # which of its cameras; default = face
//       - face: 3
//         backend: sim                    # the simulated museum (holo::simulated builds it)
//         scene: museum                   # built-in name or scene YAML (relative to this file)
//         camera: 3                       # which simulated camera; default = face
//         paced: true                     # frames at the scene's fps (default)
//
// depth_scale is in metres per raw depth unit (0.001 = millimetres; default 0.001), the unit of
// every depth scale in the project (calibration files too). A value of 1 or more is the old
// inverse convention (units per metre) and is refused with the value to write instead. Every error is a
// holo::InputError naming the file and the dotted field ("capture.cameras[1].colour.pixel_format"). Parsing
// opens nothing; makeSources() builds the sources. Capture does not link the simulation: a sim
// camera's source comes from the SourceFactory its caller passes (simulated/simulated_source.hpp).
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "holo/capture/aravis_source.hpp"
#include "holo/capture/camera_source.hpp"
#include "holo/capture/capture_thread.hpp"
#include "holo/capture/recording_source.hpp"
#include "holo/capture/v4l2_source.hpp"
#include "holo/core/config.hpp"

namespace holo::capture {

inline constexpr double kDefaultMetresPerDepthUnit = 0.001;  // millimetres
inline constexpr double kMaxMetresPerDepthUnit = 0.1;        // coarser is no depth camera

enum class Backend { Aravis, V4l2, Recording, Simulated };
const char* toString(Backend backend);

struct CameraEntry {
  int face = 0;  // 0..3, unique within the configuration
  Backend backend = Backend::Aravis;
  std::string name;  // "face0" unless given
  AravisCameraConfig aravis;
  V4l2CameraConfig v4l2;
  std::filesystem::path recording;  // Backend::Recording: the folder, relative to the config file
  int recording_camera = 0;         // which camera of the recording
  ReplayOptions replay;             // Backend::Recording: colour/depth paired within pair_tolerance_ms
  std::string scene;                // Backend::Simulated: built-in scene name or YAML file
  int sim_camera = 0;               // which simulated camera
  bool paced = true;                // Backend::Simulated: frames at the scene's rate
};

struct CaptureConfig {
  std::filesystem::path calibration_dir = "calibration";  // relative paths: to the config file
  CaptureOptions options;                                 // camera_id is set per camera by makeCaptureOptions
  double pair_tolerance_ms = kDefaultPairToleranceMs;     // two-device cameras' colour/depth pairing
  std::vector<CameraEntry> cameras;                       // sorted by face
};

// Parses a `capture` node (the section itself, not the whole file).
CaptureConfig parseCaptureConfig(const ConfigNode& capture);
// Loads FILE and parses its `capture` section (required).
CaptureConfig loadCaptureConfig(const std::filesystem::path& file);

// Builds the source (not opened) of an entry whose backend capture does not build itself
// (Backend::Simulated).
using SourceFactory = std::function<std::unique_ptr<CameraSource>(const CameraEntry&)>;

// The source for one entry (not opened). A recording is read here: InputError when it is not one.
// A sim camera's source comes from `simulated`; without one it is an InputError (the program does
// not run the simulation).
std::unique_ptr<CameraSource> makeSource(const CameraEntry& entry, const SourceFactory& simulated = {});
// The sources of every entry, in the order of config.cameras (makeSource for each).
std::vector<std::unique_ptr<CameraSource>> makeSources(const CaptureConfig& config,
                                                       const SourceFactory& simulated = {});
CaptureOptions makeCaptureOptions(const CaptureConfig& config, const CameraEntry& entry);

}  // namespace holo::capture
