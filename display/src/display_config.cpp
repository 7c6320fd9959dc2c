#include "holo/display/display_config.hpp"

#include <algorithm>

namespace holo::display {

namespace {

LayoutKind layoutFrom(const ConfigNode& node) {
  const std::string name = node.as<std::string>();
  if (name == "monitors") return LayoutKind::Monitors;
  if (name == "cross") return LayoutKind::Cross;
  node.fail("monitors or cross");
}

cv::Size sizeFrom(const ConfigNode& node) {
  if (!node.isSequence() || node.size() != 2) node.fail("a list of 2 integers [width, height]");
  const int w = node[0].as<int>();
  const int h = node[1].as<int>();
  if (w < 16 || h < 16 || w > 16384 || h > 16384) node.fail("a size between 16 and 16384 pixels per side");
  return {w, h};
}

FaceSettings faceFrom(const ConfigNode& node) {
  node.rejectUnknownKeys({"mirror", "offset", "scale", "rotation", "monitor"});
  FaceSettings face;
  face.mirror = node.get<bool>("mirror", face.mirror);
  face.offset = node.get<vec2>("offset", face.offset);
  if (std::abs(face.offset.x) > 2.0f || std::abs(face.offset.y) > 2.0f)
    node["offset"].fail("offsets within [-2, 2] view sides");
  face.scale = node.getInRange("scale", face.scale, 0.05f, 20.0f);
  face.rotation_deg = node.getInRange("rotation", face.rotation_deg, -360.0f, 360.0f);
  face.monitor = node.get<int>("monitor", face.monitor);
  if (face.monitor < -1) node["monitor"].fail("a monitor index >= 0, or -1 for the face index");
  return face;
}

}  // namespace

DisplayConfig parseDisplayConfig(const ConfigNode& node) {
  DisplayConfig config;
  config.source = node.file();
  if (node.yaml().IsNull() || !node.yaml().IsDefined()) return config;
  node.rejectUnknownKeys(
      {"layout", "output_size", "fullscreen", "exposure", "cross", "auto_fit", "faces", "eyes"});
  if (node.has("layout")) config.layout = layoutFrom(node["layout"]);
  if (node.has("output_size")) config.output_size = sizeFrom(node["output_size"]);
  config.fullscreen = node.get<bool>("fullscreen", config.fullscreen);
  config.exposure = node.getInRange("exposure", config.exposure, 1e-6f, 1e6f);
  if (const auto cross = node.find("cross")) {
    cross->rejectUnknownKeys({"view_size", "gap"});
    config.cross_view_size = cross->getInRange("view_size", config.cross_view_size, 0.01f, 1.0f);
    config.cross_gap = cross->getInRange("gap", config.cross_gap, 0.0f, 0.5f);
    if (config.cross_view_size + config.cross_gap > 0.5f + 1e-4f)
      cross->fail("view_size + gap <= 0.5 so that the four views stay on the screen");
  }
  if (const auto fit = node.find("auto_fit")) {
    fit->rejectUnknownKeys({"enabled", "margin", "threshold"});
    config.auto_fit.enabled = fit->get<bool>("enabled", config.auto_fit.enabled);
    config.auto_fit.margin = fit->getInRange("margin", config.auto_fit.margin, 0.0f, 2.0f);
    config.auto_fit.threshold = fit->getInRange("threshold", config.auto_fit.threshold, 0.0f, 1.0f);
  }
  if (const auto faces = node.find("faces")) {
    if (!faces->isSequence() || faces->size() != kFaceCount)
      faces->fail("a list of exactly 4 faces (front +Z, right +X, back -Z, left -X)");
    for (std::size_t f = 0; f < kFaceCount; ++f) config.faces[f] = faceFrom((*faces)[f]);
  }
  return config;
}

DisplayConfig displayConfigOf(const ConfigNode& root) {
  if (!root.isMap()) {
    if (root.yaml().IsNull()) return {};
    root.fail("a map with a 'display' section");
  }
  const auto section = root.find("display");
  DisplayConfig config = section ? parseDisplayConfig(*section) : DisplayConfig{};
  config.source = root.file();
  return config;
}

DisplayConfig loadDisplayConfig(const std::filesystem::path& path) {
  return displayConfigOf(ConfigNode::loadFile(path));
}

EyeTrackerSettings parseEyeTrackerSettings(const ConfigNode& node) {
  EyeTrackerSettings e;
  if (node.yaml().IsNull() || !node.yaml().IsDefined()) return e;
  node.rejectUnknownKeys({"floor_y", "default_eye_height", "default_distance", "min_head_top", "max_head_top",
                          "min_distance", "max_distance", "head_radius", "head_depth", "min_support",
                          "top_band", "min_top_support", "eye_below_top", "alpha", "beta", "max_speed",
                          "gate", "lost_timeout_s"});
  e.floor_y = node.getInRange("floor_y", e.floor_y, -10.0f, 10.0f);
  e.default_eye_height = node.getInRange("default_eye_height", e.default_eye_height, 0.3f, 2.5f);
  e.default_distance = node.getInRange("default_distance", e.default_distance, 0.1f, 10.0f);
  e.min_head_top = node.getInRange("min_head_top", e.min_head_top, 0.3f, 2.5f);
  e.max_head_top = node.getInRange("max_head_top", e.max_head_top, 0.3f, 3.0f);
  if (e.max_head_top <= e.min_head_top) node["max_head_top"].fail("a height above min_head_top");
  e.min_distance = node.getInRange("min_distance", e.min_distance, 0.0f, 10.0f);
  e.max_distance = node.getInRange("max_distance", e.max_distance, 0.1f, 20.0f);
  if (e.max_distance <= e.min_distance) node["max_distance"].fail("a distance above min_distance");
  e.head_radius = node.getInRange("head_radius", e.head_radius, 0.03f, 0.5f);
  e.head_depth = node.getInRange("head_depth", e.head_depth, 0.05f, 1.0f);
  e.min_support = node.get<int>("min_support", e.min_support);
  if (e.min_support < 1) node["min_support"].fail("an integer >= 1");
  e.top_band = node.getInRange("top_band", e.top_band, 0.005f, 0.5f);
  e.min_top_support = node.get<int>("min_top_support", e.min_top_support);
  if (e.min_top_support < 1) node["min_top_support"].fail("an integer >= 1");
  e.eye_below_top = node.getInRange("eye_below_top", e.eye_below_top, 0.0f, 0.5f);
  e.alpha = node.getInRange("alpha", e.alpha, 0.01f, 1.0f);
  e.beta = node.getInRange("beta", e.beta, 0.0f, 1.99f);
  e.max_speed = node.getInRange("max_speed", e.max_speed, 0.1f, 20.0f);
  e.gate = node.getInRange("gate", e.gate, 0.05f, 5.0f);
  e.lost_timeout_s = node.getInRange("lost_timeout_s", static_cast<float>(e.lost_timeout_s), 0.0f, 600.0f);
  return e;
}

EyeTrackerSettings loadEyeTrackerSettings(const std::filesystem::path& path) {
  const ConfigNode root = ConfigNode::loadFile(path);
  if (!root.isMap()) {
    if (root.yaml().IsNull()) return {};
    root.fail("a map with a 'display' section");
  }
  const auto display = root.find("display");
  if (!display || !display->isMap()) return {};
  const auto eyes = display->find("eyes");
  return eyes ? parseEyeTrackerSettings(*eyes) : EyeTrackerSettings{};
}

LayoutKind parseLayoutKind(const std::string& name, const std::string& origin) {
  if (name == "monitors") return LayoutKind::Monitors;
  if (name == "cross") return LayoutKind::Cross;
  throw InputError(origin, "--layout", "monitors or cross", "'" + name + "'");
}

}  // namespace holo::display
