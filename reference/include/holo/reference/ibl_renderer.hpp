// Evaluation only: a reference for measuring the appliance's renderer, never linked by it
// (reference/CMakeLists.txt).
// The IBL renderer: the relic shaded from prefiltered maps alone (no visibility, no
// interreflection), one primary ray per pixel centre. With the foreground reprojected into the
// map (foreground_environment.hpp) this is the paper's IBL baseline. Same view and GT conventions
// as the path tracer: pixels that miss the relic are 0. Output: linear HDR CV_32FC3 BGR.
#pragma once

#include "holo/core/camera_model.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::reference {

cv::Mat renderIbl(const reflect::RenderScene& scene, const reflect::PrefilteredIbl& ibl,
                  const CameraModel& camera);

}  // namespace holo::reference
