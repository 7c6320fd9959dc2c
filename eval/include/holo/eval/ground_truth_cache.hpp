// Path-traced ground truths ("gt" of methods.hpp) kept on disk between evaluations. A truth is
// stored under a key that hashes everything it depends on: the relic's and the hall's geometry
// (positions, normals, uvs, triangles), materials and textures (so a relic file's contents, not
// its name), the visitors' geometry (when they are rendered), the panorama's pixels, the view
// (pose, intrinsics, size) bit for bit, the samples per pixel, the seed and
// reference::kPathTracerVersion. Anything else changing the truth must enter the key too.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "holo/core/camera_model.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/reference/path_tracer.hpp"

namespace holo::eval {

// The cache file's name for this truth: "gt-<64-bit hex hash>-<width>x<height>-spp<N>.exr".
// `tracer_version` is reference::kPathTracerVersion; tests pass another to see the key follow it.
std::string groundTruthKey(const ReflectionScene& scene, const CameraModel& camera, int spp,
                           bool with_visitors, std::uint64_t seed = 1,
                           int tracer_version = reference::kPathTracerVersion);

// The ground truth (linear HDR CV_32FC3 BGR), from `cache` when it holds it, else rendered and
// stored there atomically.
cv::Mat cachedGroundTruth(const ReflectionScene& scene, const CameraModel& camera, int spp,
                          bool with_visitors, const std::filesystem::path& cache);

}  // namespace holo::eval
