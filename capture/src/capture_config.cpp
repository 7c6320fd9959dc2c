#include "holo/capture/capture_config.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "holo/capture/recording_source.hpp"
#include "holo/core/error.hpp"

namespace holo::capture {

namespace {

namespace fs = std::filesystem;

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// A misspelt key would otherwise be ignored silently and the default used.
int positive(const ConfigNode& node, const std::string& key, int fallback) {
  if (!node.has(key)) return fallback;
  const int value = node[key].as<int>();
  if (value < 0) node[key].fail("a number >= 0");
  return value;
}

double rate(const ConfigNode& node, const std::string& key) {
  if (!node.has(key)) return 0.0;
  const double value = node[key].as<double>();
  if (value < 0 || value > 1000) node[key].fail("a frame rate in Hz between 0 (keep) and 1000");
  return value;
}

// Metres per raw depth unit. Before 2026-11-25 this field was the inverse (units per metre,
// 1000 for millimetres); a value that can only be that is refused with the conversion spelled
// out rather than silently inverted, so an old file is fixed once, knowingly.
double depthScale(const ConfigNode& node) {
  if (!node.has("depth_scale")) return kDefaultMetresPerDepthUnit;
  const double value = node["depth_scale"].as<double>();
  if (value >= 1.0 && std::isfinite(value))
    node["depth_scale"].fail(
        "metres per raw depth unit (0.001 = millimetres); " + fmt::format("{:g}", value) +
        " looks like units per metre, the old convention: write " + fmt::format("{:g}", 1.0 / value));
  if (!(value > 0.0 && value <= kMaxMetresPerDepthUnit))
    node["depth_scale"].fail("metres per raw depth unit in (0, 0.1] (0.001 = millimetres)");
  return value;
}

PixelFormat pixelFormat(const ConfigNode& node, bool depth, const std::vector<PixelFormat>& allowed) {
  const ConfigNode field = node["pixel_format"];
  std::vector<std::string> names;
  for (PixelFormat f : allowed) names.push_back(toString(f));
  const std::string expected = std::string(depth ? "a depth format: " : "a colour format: ") + join(names);
  PixelFormat format{};
  try {
    format = pixelFormatFromName(field.as<std::string>());
  } catch (const InputError&) {
    field.fail(expected);
  }
  if (std::find(allowed.begin(), allowed.end(), format) == allowed.end()) field.fail(expected);
  return format;
}

const std::vector<PixelFormat> kAravisColour{
    PixelFormat::Mono8,    PixelFormat::Mono16,   PixelFormat::RGB8,     PixelFormat::BGR8,
    PixelFormat::BayerRG8, PixelFormat::BayerGR8, PixelFormat::BayerGB8, PixelFormat::BayerBG8};
const std::vector<PixelFormat> kAravisDepth{PixelFormat::Mono16, PixelFormat::Coord3D_C16};
const std::vector<PixelFormat> kV4l2Colour{PixelFormat::YUYV, PixelFormat::MJPEG};
const std::vector<PixelFormat> kV4l2Depth{PixelFormat::Z16};

// The fields every backend's stream shares: format (from the backend's accepted list), size,
// rate, depth scale and buffer count.
template <typename Stream>
void parseStreamFormat(const ConfigNode& node, const std::vector<PixelFormat>& accepted, bool depth,
                       Stream& s) {
  if (node.has("pixel_format")) s.pixel_format = toString(pixelFormat(node, depth, accepted));
  s.width = positive(node, "width", 0);
  s.height = positive(node, "height", 0);
  if ((s.width == 0) != (s.height == 0)) node.fail("width and height together (or neither)");
  s.frame_rate = rate(node, "frame_rate");
  s.depth_scale = depthScale(node);
  s.buffers = positive(node, "buffers", s.buffers);
}

AravisStreamConfig parseAravisStream(const ConfigNode& node, bool depth) {
  node.rejectUnknownKeys({"serial", "pixel_format", "width", "height", "frame_rate", "depth_scale", "buffers",
                          "packet_socket", "features"});
  AravisStreamConfig s;
  s.serial = node["serial"].as<std::string>();
  if (s.serial.empty()) node["serial"].fail("the camera's serial number (see `holopyramid devices`)");
  parseStreamFormat(node, depth ? kAravisDepth : kAravisColour, depth, s);
  if (node.has("packet_socket")) {
    const std::string mode = node["packet_socket"].as<std::string>();
    if (mode == "auto")
      s.packet_socket = AravisStreamConfig::PacketSocket::Auto;
    else if (mode == "on")
      s.packet_socket = AravisStreamConfig::PacketSocket::On;
    else if (mode == "off")
      s.packet_socket = AravisStreamConfig::PacketSocket::Off;
    else
      node["packet_socket"].fail("auto, on or off");
  }
  if (node.has("features")) {
    const ConfigNode features = node["features"];
    if (!features.isMap()) features.fail("a map of GenICam feature names to values");
    for (const auto& name : features.keys()) s.features.emplace_back(name, features[name].as<std::string>());
  }
  return s;
}

V4l2StreamConfig parseV4l2Stream(const ConfigNode& node, bool depth) {
  node.rejectUnknownKeys(
      {"device", "pixel_format", "width", "height", "frame_rate", "depth_scale", "buffers"});
  V4l2StreamConfig s;
  s.device = node["device"].as<std::string>();
  if (s.device.empty()) node["device"].fail("/dev/videoN, bus:BUS_INFO or serial:SERIAL");
  parseStreamFormat(node, depth ? kV4l2Depth : kV4l2Colour, depth, s);
  return s;
}

CameraEntry parseCamera(const ConfigNode& node) {
  node.rejectUnknownKeys({"face", "backend", "name", "color", "depth", "path", "camera", "scene", "paced"});
  CameraEntry e;
  e.face = node["face"].as<int>();
  if (e.face < 0 || e.face > 3) node["face"].fail("0, 1, 2 or 3 (the side facing +Z, +X, -Z, -X)");
  e.name = node.get<std::string>("name", "face" + std::to_string(e.face));
  const std::string backend = node["backend"].as<std::string>();
  if (backend == "aravis") {
    e.backend = Backend::Aravis;
    e.aravis.name = e.name;
    if (node.has("color")) e.aravis.colour = parseAravisStream(node["color"], false);
    if (node.has("depth")) e.aravis.depth = parseAravisStream(node["depth"], true);
  } else if (backend == "v4l2") {
    e.backend = Backend::V4l2;
    e.v4l2.name = e.name;
    if (node.has("color")) e.v4l2.colour = parseV4l2Stream(node["color"], false);
    if (node.has("depth")) e.v4l2.depth = parseV4l2Stream(node["depth"], true);
  } else if (backend == "recording") {
    e.backend = Backend::Recording;
    e.recording = node.pathBesideFile(node["path"].as<std::string>());
    e.recording_camera = node.get<int>("camera", e.face);
    if (e.recording_camera < 0) node["camera"].fail("a camera index >= 0");
  } else if (backend == "sim") {
    e.backend = Backend::Simulated;
    e.scene = node["scene"].as<std::string>();
    // A scene file is relative to the configuration; a built-in name stays as it is.
    if (fs::path(e.scene).has_extension()) e.scene = node.pathBesideFile(e.scene).string();
    e.sim_camera = node.get<int>("camera", e.face);
    if (e.sim_camera < 0 || e.sim_camera > 3) node["camera"].fail("a simulated camera 0..3");
    e.paced = node.get<bool>("paced", true);
  } else {
    node["backend"].fail("aravis, v4l2, recording or sim");
  }
  const bool device = e.backend == Backend::Aravis || e.backend == Backend::V4l2;
  if (device && !node.has("color") && !node.has("depth")) node.fail("a color stream, a depth stream or both");
  if (!device && (node.has("color") || node.has("depth")))
    node.fail(std::string("no color/depth streams for a ") + toString(e.backend) +
              " camera (it has its own)");
  return e;
}

std::chrono::milliseconds millis(const ConfigNode& node, const std::string& key,
                                 std::chrono::milliseconds fallback) {
  if (!node.has(key)) return fallback;
  const int value = node[key].as<int>();
  if (value <= 0 || value > 600000) node[key].fail("milliseconds between 1 and 600000");
  return std::chrono::milliseconds(value);
}

}  // namespace

const char* toString(Backend backend) {
  switch (backend) {
    case Backend::Aravis:
      return "aravis";
    case Backend::V4l2:
      return "v4l2";
    case Backend::Recording:
      return "recording";
    case Backend::Simulated:
      return "sim";
  }
  return "unknown";
}

CaptureConfig parseCaptureConfig(const ConfigNode& capture) {
  capture.rejectUnknownKeys({"calibration_dir", "grab_timeout_ms", "silence_timeout_ms", "initial_backoff_ms",
                             "max_backoff_ms", "pair_tolerance_ms", "cameras"});
  CaptureConfig config;
  if (capture.has("calibration_dir"))
    config.calibration_dir = capture.pathBesideFile(capture["calibration_dir"].as<std::string>());
  else
    config.calibration_dir = capture.pathBesideFile(config.calibration_dir);
  config.options.grab_timeout = millis(capture, "grab_timeout_ms", config.options.grab_timeout);
  config.options.silence_timeout = millis(capture, "silence_timeout_ms", config.options.silence_timeout);
  config.options.initial_backoff = millis(capture, "initial_backoff_ms", config.options.initial_backoff);
  config.options.max_backoff = millis(capture, "max_backoff_ms", config.options.max_backoff);
  if (config.options.max_backoff < config.options.initial_backoff)
    capture["max_backoff_ms"].fail("at least initial_backoff_ms");
  config.pair_tolerance_ms = capture.get<double>("pair_tolerance_ms", kDefaultPairToleranceMs);
  if (!(config.pair_tolerance_ms > 0.0 && config.pair_tolerance_ms <= 1000.0))
    capture["pair_tolerance_ms"].fail("milliseconds in (0, 1000] (default 16: half a frame at 30 Hz)");

  const ConfigNode cameras = capture["cameras"];
  if (!cameras.isSequence() || cameras.size() == 0 || cameras.size() > 4)
    cameras.fail("a list of 1 to 4 cameras");
  std::set<int> faces;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    CameraEntry e = parseCamera(cameras[i]);
    e.aravis.pair_tolerance =
        Nanoseconds(static_cast<std::int64_t>(std::llround(config.pair_tolerance_ms * 1e6)));
    e.replay.pair_tolerance = e.aravis.pair_tolerance;
    e.v4l2.pair_tolerance = e.aravis.pair_tolerance;
    if (!faces.insert(e.face).second)
      cameras[i]["face"].fail("a face no other camera has", "face " + std::to_string(e.face) + " again");
    config.cameras.push_back(std::move(e));
  }
  std::sort(config.cameras.begin(), config.cameras.end(),
            [](const CameraEntry& a, const CameraEntry& b) { return a.face < b.face; });
  return config;
}

CaptureConfig loadCaptureConfig(const fs::path& file) {
  return parseCaptureConfig(ConfigNode::loadFile(file)["capture"]);
}

std::unique_ptr<CameraSource> makeSource(const CameraEntry& entry, const SourceFactory& simulated) {
  switch (entry.backend) {
    case Backend::Aravis:
      return std::make_unique<AravisSource>(entry.aravis);
    case Backend::V4l2:
      return std::make_unique<V4l2Source>(entry.v4l2);
    case Backend::Recording: {
      Recording recording = readRecording(entry.recording);
      for (auto& camera : recording.cameras)
        if (camera.id == entry.recording_camera)
          return std::make_unique<RecordingSource>(std::move(camera), entry.replay);
      throw InputError(entry.recording.string(), "camera",
                       "a camera of the recording (it has " + std::to_string(recording.cameras.size()) + ")",
                       std::to_string(entry.recording_camera));
    }
    case Backend::Simulated:
      if (!simulated)
        throw InputError(entry.name, "backend", "a camera this program can open (aravis, v4l2 or recording)",
                         "sim (the simulated museum, which this program does not link)");
      return simulated(entry);
  }
  throw Error("unknown capture backend");
}

std::vector<std::unique_ptr<CameraSource>> makeSources(const CaptureConfig& config,
                                                       const SourceFactory& simulated) {
  std::vector<std::unique_ptr<CameraSource>> sources;
  for (const auto& entry : config.cameras) sources.push_back(makeSource(entry, simulated));
  return sources;
}

CaptureOptions makeCaptureOptions(const CaptureConfig& config, const CameraEntry& entry) {
  CaptureOptions options = config.options;
  options.camera_id = entry.face;
  return options;
}

}  // namespace holo::capture
