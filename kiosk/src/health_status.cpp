#include "holo/kiosk/health_status.hpp"

#include <fmt/format.h>
#include <cmath>

namespace holo::kiosk {
namespace {
// JSON has no NaN or Inf; a broken timer must not make the whole document invalid.
double finite(double v) {
  return std::isfinite(v) ? v : -1.0;
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
  j["state"] = state;
  j["mode"] = mode;
  j["quality"] = quality;
  j["fps"] = finite(fps);
  j["frame_ms"] = finite(frame_ms);
  j["stage_ms"] = nlohmann::json::object();
  for (const auto& [stage, ms] : stage_ms) j["stage_ms"][stage] = finite(ms);
  j["foreground_share"] = foreground_share ? nlohmann::json(finite(*foreground_share)) : nlohmann::json();
  j["cameras"] = nlohmann::json::array();
  for (const auto& c : cameras) {
    j["cameras"].push_back({{"name", c.name},
                            {"alive", c.alive},
                            {"frames", c.frames},
                            {"dropped", c.dropped},
                            {"reconnects", c.reconnects},
                            {"last_frame_age_s", finite(c.last_frame_age_s)}});
  }
  j["cameras_alive"] = camerasAlive();
  j["uptime_s"] = finite(uptime_s);
  j["frames"] = frames;
  j["seconds_since_frame"] = finite(seconds_since_frame);
  j["config"] = {{"source", config_source}, {"warning", config_warning}};
  j["last_errors"] = nlohmann::json(std::vector<std::string>(last_errors.begin(), last_errors.end()));
  return j;
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
