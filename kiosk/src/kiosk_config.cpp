#include "holo/kiosk/kiosk_config.hpp"

#include "holo/core/files.hpp"
#include "holo/core/log.hpp"
#include "holo/kiosk/listen_address.hpp"

namespace holo::kiosk {
namespace {

int positiveInt(const ConfigNode& node, const std::string& key, int fallback, int minimum) {
  if (!node.has(key)) return fallback;
  const int v = node[key].as<int>();
  if (v < minimum) node[key].fail("an integer >= " + std::to_string(minimum), std::to_string(v));
  return v;
}

}  // namespace

const std::string& factoryDefaultsYaml() {
  static const std::string text = R"(# Holopyramid factory defaults (built into the program).
kiosk:
  opening_hours: ""
  max_fps: 30
  status_interval_s: 1.0
  health:
    address: 127.0.0.1
    port: 8787
    file: /run/holopyramid/health.json
  console:
    enabled: false
    address: 127.0.0.1
    port: 8788
    secret_file: /etc/holopyramid/console.secret
    session_minutes: 60
  degradation:
    frame_budget_ms: 40
    quality_levels: [full, reduced, low, minimal]
    headroom: 0.7
    smoothing: 0.2
    down_after_frames: 10
    up_after_frames: 60
    cooldown_frames: 30
    recover_after_frames: 15
)";
  return text;
}

KioskConfig parseKioskConfig(const ConfigNode& root) {
  KioskConfig c;
  const auto section = root.find("kiosk");
  if (!section) return c;
  const ConfigNode& k = *section;
  if (!k.isMap()) k.fail("a map of kiosk settings");
  k.rejectUnknownKeys({"opening_hours", "max_fps", "status_interval_s", "health", "degradation", "console"});
  if (k.has("opening_hours")) {
    c.opening_hours_text = k["opening_hours"].as<std::string>();
    c.opening_hours = OpeningHours::parse(c.opening_hours_text, k.file(), k["opening_hours"].path());
  }
  c.max_fps = k.getInRange("max_fps", static_cast<float>(c.max_fps), 1.0f, 240.0f);
  c.status_interval_s =
      k.getInRange("status_interval_s", static_cast<float>(c.status_interval_s), 0.05f, 60.0f);
  if (const auto h = k.find("health")) {
    h->rejectUnknownKeys({"address", "port", "file"});
    c.health_address = h->get<std::string>("address", c.health_address);
    c.health_port = h->get<int>("port", c.health_port);
    if (c.health_port > 65535) (*h)["port"].fail("a TCP port up to 65535 (0 = any, negative = off)");
    c.health_file = h->get<std::string>("file", c.health_file.string());
  }
  if (const auto con = k.find("console")) {
    if (!con->isMap()) con->fail("a map of console settings");
    con->rejectUnknownKeys({"enabled", "address", "port", "secret_file", "session_minutes"});
    ConsoleSettings& s = c.console;
    s.enabled = con->get<bool>("enabled", s.enabled);
    s.address = con->get<std::string>("address", s.address);
    if (con->has("address") && !isIpAddress(s.address))
      (*con)["address"].fail("an IP address to listen on (127.0.0.1 = this machine only)", s.address);
    s.port = con->get<int>("port", s.port);
    if (s.port < 0 || s.port > 65535) (*con)["port"].fail("a TCP port 0..65535 (0 = any free port)");
    if (con->has("secret_file")) {
      const std::string file = (*con)["secret_file"].as<std::string>();
      if (file.empty()) (*con)["secret_file"].fail("the path of the console's password hash file");
      s.secret_file = con->pathBesideFile(file);
    }
    s.session_minutes = positiveInt(*con, "session_minutes", s.session_minutes, 1);
    if (s.session_minutes > 1440)
      (*con)["session_minutes"].fail("minutes a login lasts, 1..1440", std::to_string(s.session_minutes));
  }
  if (const auto d = k.find("degradation")) {
    d->rejectUnknownKeys({"frame_budget_ms", "quality_levels", "headroom", "smoothing", "down_after_frames",
                          "up_after_frames", "cooldown_frames", "recover_after_frames"});
    auto& s = c.degradation;
    s.frame_budget_ms =
        d->getInRange("frame_budget_ms", static_cast<float>(s.frame_budget_ms), 1.0f, 10000.0f);
    s.headroom = d->getInRange("headroom", static_cast<float>(s.headroom), 0.05f, 0.95f);
    s.smoothing = d->getInRange("smoothing", static_cast<float>(s.smoothing), 0.01f, 1.0f);
    s.down_after_frames = positiveInt(*d, "down_after_frames", s.down_after_frames, 1);
    s.up_after_frames = positiveInt(*d, "up_after_frames", s.up_after_frames, 1);
    s.cooldown_frames = positiveInt(*d, "cooldown_frames", s.cooldown_frames, 0);
    s.recover_after_frames = positiveInt(*d, "recover_after_frames", s.recover_after_frames, 1);
    if (d->has("quality_levels")) {
      const ConfigNode levels = (*d)["quality_levels"];
      if (!levels.isSequence() || levels.size() == 0) levels.fail("a non-empty list of level names");
      s.quality_levels.clear();
      for (std::size_t i = 0; i < levels.size(); ++i) s.quality_levels.push_back(levels[i].as<std::string>());
    }
  }
  return c;
}

LoadedConfig loadConfigWithFallback(const std::filesystem::path& path, const std::filesystem::path& last_good,
                                    const std::function<void(const ConfigNode&)>& validate) {
  const auto tryLoad = [&](const ConfigNode& root, const std::string& source) {
    LoadedConfig loaded{root, parseKioskConfig(root), source, {}};
    if (validate) validate(root);
    return loaded;
  };
  std::string warning;
  try {
    if (!std::filesystem::exists(path))
      throw InputError(path.string(), "", "a configuration file", "no such file");
    LoadedConfig loaded = tryLoad(ConfigNode::loadFile(path), path.string());
    if (!last_good.empty()) {
      try {
        writeFileAtomically(last_good, readFile(path));
      } catch (const std::exception& e) {  // the config itself is fine; keeping a copy is a bonus
        HOLO_LOG_WARN("cannot keep a last good copy of the configuration: {}", e.what());
      }
    }
    return loaded;
  } catch (const std::exception& e) {
    warning = e.what();
  }
  HOLO_LOG_ERROR("configuration {} not used: {}", path.string(), warning);
  if (!last_good.empty() && std::filesystem::exists(last_good)) {
    try {
      // Read as if it stood where the configuration stands: its relative paths (relic, panorama,
      // recordings, calibration folder) name the same files as when it was saved.
      LoadedConfig loaded = tryLoad(ConfigNode::parse(readFile(last_good), path.string()),
                                    "last good copy (" + last_good.string() + ")");
      loaded.warning = "using last good config: " + warning;
      HOLO_LOG_WARN("running with the last good configuration {}", last_good.string());
      return loaded;
    } catch (const std::exception& e) {
      HOLO_LOG_ERROR("last good configuration {} not usable either: {}", last_good.string(), e.what());
    }
  }
  LoadedConfig loaded =
      tryLoad(ConfigNode::parse(factoryDefaultsYaml(), "factory defaults"), "factory defaults");
  loaded.warning = "using factory defaults: " + warning;
  HOLO_LOG_WARN("running with the factory default configuration");
  return loaded;
}

}  // namespace holo::kiosk
