#include "holo/kiosk/health_status.hpp"

#include <fmt/format.h>
#include <cmath>

namespace holo::kiosk {
namespace {
// JSON has no NaN or Inf; a broken timer must not make the whole document invalid.
double finite(double v) {
  return std::isfinite(v) ? v : -1.0;
}

// Names come from config files and from the cameras themselves (a GigE camera reports its own
// model and serial), in no promised encoding. Prometheus label values and JSON strings must be
// UTF-8 (nlohmann's dump() throws on anything else), so every byte that does not start a valid,
// shortest-form sequence of a scalar value becomes U+FFFD.
std::string validUtf8(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  const auto byte = [&text](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char lead = byte(i);
    const std::size_t length = lead < 0x80                    ? 1
                               : lead >= 0xC2 && lead <= 0xDF ? 2
                               : lead >= 0xE0 && lead <= 0xEF ? 3
                               : lead >= 0xF0 && lead <= 0xF4 ? 4
                                                              : 0;
    bool valid = length > 0 && i + length <= text.size();
    for (std::size_t k = 1; valid && k < length; ++k) valid = (byte(i + k) & 0xC0) == 0x80;
    if (valid && length >= 3) {
      // Overlong forms, UTF-16 surrogates and code points above U+10FFFF, by the second byte.
      const unsigned char second = byte(i + 1);
      valid = !(lead == 0xE0 && second < 0xA0) && !(lead == 0xED && second >= 0xA0) &&
              !(lead == 0xF0 && second < 0x90) && !(lead == 0xF4 && second >= 0x90);
    }
    if (valid) {
      out.append(text, i, length);
      i += length;
    } else {
      out += "\xEF\xBF\xBD";  // U+FFFD REPLACEMENT CHARACTER
      ++i;
    }
  }
  return out;
}

// Label values hold whatever a config file or a camera says; the format reserves backslash,
// quote and newline.
std::string labelValue(const std::string& text) {
  const std::string value = validUtf8(text);
  std::string out;
  out.reserve(value.size());
  for (const char c : value) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '"')
      out += "\\\"";
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out;
}

std::string sampleValue(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  return fmt::format("{}", v);
}

class Exposition {
 public:
  void family(const char* name, const char* type, const char* help) {
    text_ += fmt::format("# HELP holopyramid_{} {}\n# TYPE holopyramid_{} {}\n", name, help, name, type);
  }
  void sample(const char* name, double value, const std::string& labels = {}) {
    text_ += fmt::format("holopyramid_{}{} {}\n", name, labels.empty() ? "" : "{" + labels + "}",
                         sampleValue(value));
  }
  std::string take() { return std::move(text_); }

 private:
  std::string text_;
};

std::string label(const char* key, const std::string& value) {
  return fmt::format("{}=\"{}\"", key, labelValue(value));
}
}  // namespace

void HealthStatus::addError(const std::string& message) {
  last_errors.push_back(message);
  while (last_errors.size() > kMaxErrors) last_errors.pop_front();
}

int HealthStatus::camerasAlive() const {
  int n = 0;
  for (const auto& c : cameras) n += c.alive ? 1 : 0;
  return n;
}

nlohmann::json HealthStatus::toJson() const {
  nlohmann::json j;
  j["state"] = validUtf8(state);
  j["mode"] = validUtf8(mode);
  j["quality"] = validUtf8(quality);
  j["quality_level"] = quality_level;
  j["frame_budget_ms"] = finite(frame_budget_ms);
  j["target_fps"] = finite(target_fps);
  j["fps"] = finite(fps);
  j["frame_ms"] = finite(frame_ms);
  j["stage_ms"] = nlohmann::json::object();
  for (const auto& [stage, ms] : stage_ms) j["stage_ms"][validUtf8(stage)] = finite(ms);
  j["foreground_share"] = foreground_share ? nlohmann::json(finite(*foreground_share)) : nlohmann::json();
  j["camera_skew_ms"] = camera_skew_ms ? nlohmann::json(finite(*camera_skew_ms)) : nlohmann::json();
  j["cameras"] = nlohmann::json::array();
  for (const auto& c : cameras) {
    j["cameras"].push_back({{"name", validUtf8(c.name)},
                            {"alive", c.alive},
                            {"frames", c.frames},
                            {"dropped", c.dropped},
                            {"reconnects", c.reconnects},
                            {"last_frame_age_s", finite(c.last_frame_age_s)},
                            {"unpaired", c.unpaired},
                            {"pair_skew_ms", finite(c.pair_skew_ms)}});
  }
  j["cameras_alive"] = camerasAlive();
  j["uptime_s"] = finite(uptime_s);
  j["frames"] = frames;
  j["seconds_since_frame"] = finite(seconds_since_frame);
  j["config"] = {{"source", validUtf8(config_source)}, {"warning", validUtf8(config_warning)}};
  j["relic"] = validUtf8(relic);
  j["next_relic"] = validUtf8(next_relic);
  j["exhibit_problems"] = nlohmann::json::array();
  for (const auto& problem : exhibit_problems) j["exhibit_problems"].push_back(validUtf8(problem));
  j["last_errors"] = nlohmann::json::array();
  for (const auto& error : last_errors) j["last_errors"].push_back(validUtf8(error));
  return j;
}

std::string HealthStatus::toPrometheus() const {
  Exposition e;
  e.family("info", "gauge", "Always 1; the labels carry the state, render mode and quality level.");
  e.sample("info", 1, label("state", state) + "," + label("mode", mode) + "," + label("quality", quality));
  e.family("quality_level", "gauge", "The degradation level: 0 = full quality, higher = more degraded.");
  e.sample("quality_level", quality_level);
  e.family("frame_budget_seconds", "gauge", "The frame time the degradation policy keeps under.");
  e.sample("frame_budget_seconds", frame_budget_ms / 1000.0);
  e.family("target_frames_per_second", "gauge",
           "The frame rate aimed at: kiosk.max_fps, or fewer when the frame budget allows fewer.");
  e.sample("target_frames_per_second", target_fps);
  e.family("frames_per_second", "gauge", "Frame rate over the last second or so.");
  e.sample("frames_per_second", fps);
  e.family("frame_seconds", "gauge", "Smoothed frame time.");
  e.sample("frame_seconds", frame_ms / 1000.0);
  e.family("stage_seconds", "gauge", "The last frame's time per pipeline stage.");
  for (const auto& [stage, ms] : stage_ms) e.sample("stage_seconds", ms / 1000.0, label("stage", stage));
  if (foreground_share) {
    e.family("foreground_share", "gauge", "Fraction of view pixels showing foreground.");
    e.sample("foreground_share", *foreground_share);
  }
  if (camera_skew_ms) {
    e.family("camera_skew_seconds", "gauge",
             "Spread of the arrival times of the camera frames the last frame was made of.");
    e.sample("camera_skew_seconds", *camera_skew_ms / 1000.0);
  }
  e.family("frames_total", "counter", "Frames rendered since start.");
  e.sample("frames_total", static_cast<double>(frames));
  e.family("uptime_seconds", "gauge", "Seconds since the kiosk started.");
  e.sample("uptime_seconds", uptime_s);
  e.family("seconds_since_frame", "gauge", "Seconds since the last frame; grows when the frame loop hangs.");
  e.sample("seconds_since_frame", seconds_since_frame);
  e.family("cameras", "gauge", "Cameras configured.");
  e.sample("cameras", static_cast<double>(cameras.size()));
  e.family("cameras_alive", "gauge", "Cameras that delivered a fresh frame recently.");
  e.sample("cameras_alive", camerasAlive());
  e.family("camera_up", "gauge", "1 when the camera delivered a fresh frame recently.");
  for (const auto& c : cameras) e.sample("camera_up", c.alive ? 1 : 0, label("camera", c.name));
  e.family("camera_frames_total", "counter", "Frames received from the camera.");
  for (const auto& c : cameras)
    e.sample("camera_frames_total", static_cast<double>(c.frames), label("camera", c.name));
  e.family("camera_dropped_frames_total", "counter", "Frames dropped (late, corrupt).");
  for (const auto& c : cameras)
    e.sample("camera_dropped_frames_total", static_cast<double>(c.dropped), label("camera", c.name));
  e.family("camera_reconnects_total", "counter", "Times the camera was reopened.");
  for (const auto& c : cameras)
    e.sample("camera_reconnects_total", static_cast<double>(c.reconnects), label("camera", c.name));
  e.family("camera_last_frame_age_seconds", "gauge", "Seconds since the camera's newest frame.");
  for (const auto& c : cameras)
    e.sample("camera_last_frame_age_seconds", c.last_frame_age_s, label("camera", c.name));
  e.family("camera_unpaired_frames_total", "counter",
           "Colour and depth frames of a two-device camera dropped for want of a partner in time.");
  for (const auto& c : cameras)
    e.sample("camera_unpaired_frames_total", static_cast<double>(c.unpaired), label("camera", c.name));
  e.family("camera_pair_skew_seconds", "gauge", "A two-device camera's last depth - colour arrival time.");
  for (const auto& c : cameras)
    e.sample("camera_pair_skew_seconds", c.pair_skew_ms / 1000.0, label("camera", c.name));
  e.family("recent_errors", "gauge", "Errors kept in the health JSON's last_errors (at most 10).");
  e.sample("recent_errors", static_cast<double>(last_errors.size()));
  e.family("exhibit_problems", "gauge", "Exhibit playlist entries skipped because they did not load.");
  e.sample("exhibit_problems", static_cast<double>(exhibit_problems.size()));
  e.family("config_fallback", "gauge",
           "1 when the configured file was not used (see the health JSON's config).");
  e.sample("config_fallback", config_warning.empty() ? 0 : 1);
  return e.take();
}

std::string HealthStatus::summary() const {
  std::string s = fmt::format("cameras {}/{}, {:.1f} fps", camerasAlive(), cameras.size(), finite(fps));
  if (foreground_share) s += fmt::format(", fg {:.0f}%", 100.0 * finite(*foreground_share));
  s += fmt::format(", mode {}, quality {}", mode, quality);
  if (state != "running") s += ", " + state;
  if (!config_warning.empty()) s += ", CONFIG: " + config_warning;
  // STATUS= is one line: a newline would end the field and start a bogus assignment.
  for (auto& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

}  // namespace holo::kiosk
