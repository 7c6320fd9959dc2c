#include "holo/eval/method_sweep.hpp"

#include "holo/eval/ground_truth_cache.hpp"
#include "holo/reference/image_metrics.hpp"

namespace holo::eval {

// The (method, knob) points: the first of each method is its default (the one "methods" in the
// JSON reports); the rest trace the time/error curve.
std::vector<MethodPoint> plannedMethodPoints(bool full, int gt_spp) {
  std::vector<MethodPoint> points;
  const auto add = [&](const std::string& method, const std::string& knob, MethodSettings s) {
    points.push_back({method, knob, s, 0, 0, 0, {}});
  };
  for (int spp : full ? std::vector<int>{16, 1, 4, 64, 256} : std::vector<int>{16, 1, 4}) {
    if (spp >= gt_spp) continue;
    MethodSettings s;
    s.spp = spp;
    s.seed = 7;  // independent of the ground truth's samples
    add("gt", "spp=" + std::to_string(spp), s);
  }
  const std::vector<std::pair<int, int>> ibl =
      full ? std::vector<std::pair<int, int>>{{10, 20}, {5, 8}, {10, 8}, {10, 40}, {17, 40}}
           : std::vector<std::pair<int, int>>{{10, 20}, {5, 8}};
  add("ours", "aa=4,levels=7", {});
  for (int rays : full ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 4}) {
    MethodSettings s;
    s.spp = rays;
    add("ssrt", "rays=" + std::to_string(rays), s);
  }
  for (int spp : full ? std::vector<int>{4, 1, 16, 64, 256} : std::vector<int>{4, 1}) {
    MethodSettings s;
    s.spp = spp;
    s.seed = 7;
    add("mcpt", "spp=" + std::to_string(spp), s);
  }
  for (const std::string method : {"ibl", "ibl-baseline"})
    for (auto [levels, density] : ibl) {
      MethodSettings s;
      s.ibl_levels = levels;
      s.ibl_texel_density = density;
      add(method, "levels=" + std::to_string(levels) + ",density=" + std::to_string(density), s);
    }
  return points;
}

MethodSweep sweepMethods(const ReflectionScene& scene, const CameraModel& camera, bool full, int gt_spp,
                         const std::string& cache) {
  MethodSweep sweep;
  sweep.truth = cachedGroundTruth(scene, camera, gt_spp, true, cache);
  sweep.region = cv::Mat(sweep.truth.size(), CV_8UC1, cv::Scalar(0));
  if (!scene.visitors.meshes.empty())
    sweep.region =
        reference::foregroundRegion(sweep.truth, cachedGroundTruth(scene, camera, gt_spp, false, cache));
  sweep.region_pixels = cv::countNonZero(sweep.region);
  sweep.points = plannedMethodPoints(full, gt_spp);
  for (MethodPoint& p : sweep.points) {
    const MethodResult r = renderMethod(p.method, scene, camera, p.settings);
    p.ms = r.ms;
    p.image = r.image;
    p.mse = reference::mse(r.image, sweep.truth);
    p.fg_mse = sweep.region_pixels > 0 ? reference::mse(r.image, sweep.truth, sweep.region) : 0.0;
  }
  return sweep;
}

}  // namespace holo::eval
