// The reports of the method sweep (`holopyramid eval reflections`, method_sweep.hpp): the JSON
// (the view, each method's default setting and every point), the CSV of every (time, error)
// point, the log-log plot of error against time per view (SVG) and the images: the truth and each
// method's default tone-mapped at the truth's exposure (so they stay comparable), each one's error
// map, the foreground region and a side-by-side strip.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/eval/method_sweep.hpp"
#include "holo/eval/reflection_scene.hpp"

namespace holo::eval {

// scene, relic, width, height, gt_spp, fg_pixels, methods (each method's first point: fg_mse,
// mse, ms, knob) and points (every point, with its method).
nlohmann::json methodSweepJson(const ReflectionScene& scene, const CameraModel& camera, int gt_spp,
                               const MethodSweep& sweep);

// method, knob, ms, mse, fg_mse per point.
void writeMethodSweepCsv(const std::string& path, const std::vector<MethodPoint>& points);

// Error (MSE, and foreground MSE dashed) against time per view, log-log, one series per method.
void writeMethodSweepSvg(const std::string& path, const std::vector<MethodPoint>& points,
                         const std::string& title);

// Into `dir` (created): gt_reference.png, foreground_region.png, METHOD.png and METHOD_error.png
// for each method's default setting, side_by_side.png.
void writeMethodSweepImages(const std::filesystem::path& dir, const MethodSweep& sweep);

}  // namespace holo::eval
