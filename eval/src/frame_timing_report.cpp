#include "holo/eval/frame_timing_report.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <nlohmann/json.hpp>

#include "holo/core/median.hpp"

namespace holo::eval {

using pipeline::CameraFrameCounts;
using pipeline::FrameReport;
using pipeline::kPassCount;
using pipeline::StageTimes;

namespace {

std::int64_t totalNonFinite(const std::vector<FrameReport>& reports) {
  std::int64_t n = 0;
  for (const FrameReport& r : reports) n += r.non_finite_pixels;
  return n;
}

}  // namespace

StageTimes medianTimes(const std::vector<FrameReport>& reports) {
  auto pick = [&](double StageTimes::*field) {
    std::vector<double> values;
    for (const FrameReport& r : reports) values.push_back(r.times.*field);
    return median(values);
  };
  StageTimes m;
  m.acquisition = pick(&StageTimes::acquisition);
  m.foreground = pick(&StageTimes::foreground);
  m.dynamic = pick(&StageTimes::dynamic);
  m.statics = pick(&StageTimes::statics);
  m.composition = pick(&StageTimes::composition);
  m.display = pick(&StageTimes::display);
  m.total = pick(&StageTimes::total);
  m.pipeline_wait = pick(&StageTimes::pipeline_wait);
  return m;
}

std::vector<std::pair<std::string, double>> medianPasses(const std::vector<FrameReport>& reports) {
  std::vector<std::pair<std::string, double>> out;
  for (std::size_t p = 0; p <= kPassCount; ++p) {
    std::vector<double> values;
    for (const FrameReport& r : reports) values.push_back(p < kPassCount ? r.pass_ms[p] : r.camera_images_ms);
    out.emplace_back(p < kPassCount ? reflect::passName(static_cast<reflect::Pass>(p)) : "CameraImages",
                     median(values));
  }
  return out;
}

std::string formatTimingTable(const StageTimes& m, const std::vector<FrameReport>& reports,
                              const CameraFrameCounts& cameras) {
  std::string out;
  const auto row = [&out](const char* name, double ms) { out += fmt::format("{:<34} {:9.2f}\n", name, ms); };
  const auto fps = [](double ms) { return ms > 0 ? 1000.0 / ms : 0.0; };
  out += fmt::format("{:<34} median ms   (over {} frames)\n", "stage", reports.size());
  if (!cameras.simulated) row("acquisition (wait)", m.acquisition);
  row("foreground point cloud", m.foreground);
  row("dynamic reflections", m.dynamic);
  row("static reflections", m.statics);
  row("composition", m.composition);
  row("display", m.display);
  row("appliance stages, one after another", m.applianceStages());
  row("  frames per second, no overlap", fps(m.applianceStages()));
  if (cameras.simulated) {
    out += "simulating the cameras (no real installation pays this):\n";
    row("  acquisition (wait)", m.acquisition);
  }
  row("waiting for the foreground", m.pipeline_wait);
  row(cameras.simulated ? "whole frame, simulation included" : "whole frame", m.total);
  row("  frames per second", fps(m.total));
  if (cameras.simulated)
    out += "the appliance's own frame rate, cameras simulated before timing: holopyramid bench frame\n";
  out += fmt::format("{:<34} {:9}\n", "non-finite HDR pixels", totalNonFinite(reports));
  out += fmt::format(
      "camera frames ({}): {} produced, {} consumed, {} dropped, {} never consumed, {} unusable\n",
      cameras.live ? "live" : "deterministic: none dropped by construction", cameras.produced,
      cameras.consumed, cameras.dropped, cameras.unconsumed, cameras.rejected);
  return out;
}

std::string timingJson(const StageTimes& m, const std::vector<FrameReport>& reports,
                       const CameraFrameCounts& cameras) {
  auto stages = [](const StageTimes& t) {
    return nlohmann::json{{"acquisition_ms", t.acquisition},     {"foreground_ms", t.foreground},
                          {"dynamic_reflections_ms", t.dynamic}, {"static_reflections_ms", t.statics},
                          {"composition_ms", t.composition},     {"display_ms", t.display},
                          {"pipeline_wait_ms", t.pipeline_wait}, {"frame_ms", t.total}};
  };
  nlohmann::json j;
  j["frames"] = reports.size();
  j["stages_ms"] = stages(m);  // medians over the frames
  j["frame_ms"] = m.total;
  j["fps"] = m.total > 0 ? 1000.0 / m.total : 0.0;
  j["appliance_stages_ms"] = m.applianceStages();
  j["appliance_fps"] = m.applianceStages() > 0 ? 1000.0 / m.applianceStages() : 0.0;
  j["simulated_cameras"] = cameras.simulated;
  j["non_finite_pixels"] = totalNonFinite(reports);
  j["camera_frames"] = {{"mode", cameras.live ? "live" : "deterministic"},
                        {"produced", cameras.produced},
                        {"consumed", cameras.consumed},
                        {"dropped", cameras.dropped},
                        {"unconsumed", cameras.unconsumed},
                        {"rejected", cameras.rejected}};
  nlohmann::json per_frame = nlohmann::json::array();
  for (const FrameReport& r : reports) {
    nlohmann::json f = stages(r.times);
    f["index"] = r.index;
    f["foreground_points"] = r.foreground_points;
    f["cameras_live"] = r.cameras_live;
    f["plan"] = r.plan;
    f["non_finite_pixels"] = r.non_finite_pixels;
    f["dropped_frames"] = r.dropped_frames;
    f["static_reused_views"] = r.static_reused_views;
    f["static_deferred_views"] = r.static_deferred_views;
    f["refined_pixels"] = r.refined_pixels;
    f["relic_pixels"] = r.relic_pixels;
    f["refraction_rays"] = r.refraction_rays;
    f["refracted_walks"] = r.refracted_walks;
    f["supersampled_samples"] = r.supersampled_samples;
    f["shaded_samples"] = r.shaded_samples;
    f["interreflected_samples"] = r.interreflected_samples;
    f["interreflection_rays"] = r.interreflection_rays;
    if (const double latency = r.arrivalToPresentMs(); latency >= 0) {
      const pipeline::LatencyParts parts = r.latencyParts();
      f["latency_ms"] = {{"total", latency},
                         {"in_mailbox", parts.in_mailbox},
                         {"foreground", parts.foreground},
                         {"waiting_for_loop", parts.waiting_for_loop},
                         {"rendering", parts.rendering},
                         {"presenting", parts.presenting}};
    }
    nlohmann::json passes;
    for (std::size_t p = 0; p < kPassCount; ++p)
      passes[reflect::passName(static_cast<reflect::Pass>(p))] = r.pass_ms[p];
    passes["CameraImages"] = r.camera_images_ms;
    f["passes_ms"] = passes;
    per_frame.push_back(f);
  }
  j["per_frame"] = per_frame;
  return j.dump(2);
}

}  // namespace holo::eval
