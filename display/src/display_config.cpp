#include "holo/display/display_config.hpp"

#include <algorithm>
#include <set>

namespace holo::display {

namespace {

void rejectUnknownKeys(const ConfigNode& node, const std::set<std::string>& known) {
  if (!node.isMap()) node.fail("a map");
  for (const std::string& key : node.keys()) {
    if (known.count(key)) continue;
    std::string names;
    for (const auto& name : known) names += (names.empty() ? "" : ", ") + name;
    node[key].fail("one of the fields " + names, "unknown field '" + key + "'");
  }
}

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
  rejectUnknownKeys(node, {"mirror", "offset", "scale", "rotation", "monitor"});
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
  rejectUnknownKeys(node, {"layout", "output_size", "fullscreen", "exposure", "cross", "auto_fit", "faces"});
  if (node.has("layout")) config.layout = layoutFrom(node["layout"]);
  if (node.has("output_size")) config.output_size = sizeFrom(node["output_size"]);
  config.fullscreen = node.get<bool>("fullscreen", config.fullscreen);
  config.exposure = node.getInRange("exposure", config.exposure, 1e-6f, 1e6f);
  if (const auto cross = node.find("cross")) {
    rejectUnknownKeys(*cross, {"view_size", "gap"});
    config.cross_view_size = cross->getInRange("view_size", config.cross_view_size, 0.01f, 1.0f);
    config.cross_gap = cross->getInRange("gap", config.cross_gap, 0.0f, 0.5f);
    if (config.cross_view_size + config.cross_gap > 0.5f + 1e-4f)
      cross->fail("view_size + gap <= 0.5 so that the four views stay on the screen");
  }
  if (const auto fit = node.find("auto_fit")) {
    rejectUnknownKeys(*fit, {"enabled", "margin", "threshold"});
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

DisplayConfig loadDisplayConfig(const std::filesystem::path& path) {
  const ConfigNode root = ConfigNode::loadFile(path);
  if (!root.isMap()) {
    if (root.yaml().IsNull()) return {};
    root.fail("a map with a 'display' section");
  }
  const auto section = root.find("display");
  DisplayConfig config = section ? parseDisplayConfig(*section) : DisplayConfig{};
  config.source = path.string();
  return config;
}

LayoutKind parseLayoutKind(const std::string& name, const std::string& origin) {
  if (name == "monitors") return LayoutKind::Monitors;
  if (name == "cross") return LayoutKind::Cross;
  throw InputError(origin, "--layout", "monitors or cross", "'" + name + "'");
}

}  // namespace holo::display
