#include "holo/eval/method_sweep_report.hpp"

#include <algorithm>
#include <map>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "holo/core/files.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/eval/loglog_plot.hpp"
#include "holo/reference/image_metrics.hpp"
#include "holo/reflect/tone_map.hpp"

namespace holo::eval {

nlohmann::json methodSweepJson(const ReflectionScene& scene, const CameraModel& camera, int gt_spp,
                               const MethodSweep& sweep) {
  nlohmann::json j;
  j["scene"] = scene.scene_name;
  j["relic"] = scene.relic_name;
  j["width"] = camera.width();
  j["height"] = camera.height();
  j["gt_spp"] = gt_spp;
  j["fg_pixels"] = sweep.region_pixels;
  j["methods"] = nlohmann::json::object();
  j["points"] = nlohmann::json::array();
  for (const MethodPoint& p : sweep.points) {
    const nlohmann::json entry = {{"fg_mse", p.fg_mse}, {"mse", p.mse}, {"ms", p.ms}, {"knob", p.knob}};
    if (!j["methods"].contains(p.method)) j["methods"][p.method] = entry;
    nlohmann::json point = entry;
    point["method"] = p.method;
    j["points"].push_back(point);
  }
  return j;
}

void writeMethodSweepCsv(const std::string& path, const std::vector<MethodPoint>& points) {
  std::ostringstream out;
  out << "method,knob,ms,mse,fg_mse\n";
  for (const MethodPoint& p : points)
    out << p.method << ",\"" << p.knob << "\"," << p.ms << "," << p.mse << "," << p.fg_mse << "\n";
  writeFileAtomically(path, out.str());
}

void writeMethodSweepSvg(const std::string& path, const std::vector<MethodPoint>& points,
                         const std::string& title) {
  LogLogPlot plot{title, "time per view (ms)", "MSE", "dashed: foreground MSE", 640, 420, {}};
  const std::vector<std::pair<std::string, std::string>> colours = {
      {"gt", "#1f77b4"},   {"ibl", "#2ca02c"},  {"ibl-baseline", "#d62728"},
      {"ours", "#000000"}, {"ssrt", "#9467bd"}, {"mcpt", "#ff7f0e"}};
  for (const auto& [method, colour] : colours) {
    std::vector<const MethodPoint*> ps;
    for (const MethodPoint& p : points)
      if (p.method == method) ps.push_back(&p);
    if (ps.empty()) continue;
    std::sort(ps.begin(), ps.end(), [](const MethodPoint* a, const MethodPoint* b) { return a->ms < b->ms; });
    PlotSeries all{method, colour, {}, true, false, 3, true};
    PlotSeries foreground{method + " foreground", colour, {}, true, true, 3, false};
    for (const MethodPoint* p : ps) {
      all.markers.push_back({p->ms, p->mse, p->method + " " + p->knob, true});
      foreground.markers.push_back({p->ms, p->fg_mse, p->method + " " + p->knob + " (foreground)", true});
    }
    plot.series.push_back(std::move(all));
    plot.series.push_back(std::move(foreground));
  }
  writeFileAtomically(path, svgOf(plot));
}

void writeMethodSweepImages(const std::filesystem::path& dir, const MethodSweep& sweep) {
  const cv::Mat& gt = sweep.truth;
  std::filesystem::create_directories(dir);
  const float exposure = reflect::autoExposure(gt);  // one exposure: images stay comparable
  std::vector<cv::Mat> strip = {reflect::toneMap(gt, exposure)};
  display::writePngAtomically(dir / "gt_reference.png", strip.front());
  cv::Mat region_bgr;
  cv::cvtColor(sweep.region, region_bgr, cv::COLOR_GRAY2BGR);
  display::writePngAtomically(dir / "foreground_region.png", region_bgr);
  std::map<std::string, bool> seen;
  for (const MethodPoint& p : sweep.points) {
    if (seen[p.method]) continue;  // the default setting of each method
    seen[p.method] = true;
    const cv::Mat ldr = reflect::toneMap(p.image, exposure);
    display::writePngAtomically(dir / (p.method + ".png"), ldr);
    display::writePngAtomically(dir / (p.method + "_error.png"), reference::errorMap(p.image, gt));
    strip.push_back(ldr);
  }
  cv::Mat side_by_side;
  cv::hconcat(strip, side_by_side);
  display::writePngAtomically(dir / "side_by_side.png", side_by_side);
}

}  // namespace holo::eval
