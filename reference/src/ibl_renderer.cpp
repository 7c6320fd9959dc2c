#include "holo/reference/ibl_renderer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "holo/core/image.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "holo/reflect/view.hpp"

namespace holo::reference {

using reflect::PrefilteredIbl;
using reflect::primaryRay;
using reflect::RenderScene;
using reflect::resolveSurface;
using reflect::shadeSurface;
using reflect::SplitSumShading;
using reflect::SurfacePoint;

cv::Mat renderIbl(const RenderScene& scene, const PrefilteredIbl& ibl, const CameraModel& camera) {
  cv::Mat out(camera.height(), camera.width(), CV_32FC3, cv::Scalar::all(0));
  const RayScene& relic = scene.relicOnly();
  tbb::parallel_for(tbb::blocked_range<int>(0, out.rows), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < out.cols; ++x) {
        const Ray ray = primaryRay(camera, vec2(x, y));
        const RayHit hit = relic.intersect(ray);
        if (!hit.hit()) continue;
        const SurfacePoint s = resolveSurface(scene, relic, ray, hit, hit.t / camera.intrinsics().fx);
        const SplitSumShading parts = shadeSurface(ibl, s, -ray.direction);
        const vec3 c = parts.specular_scale * parts.environment + parts.diffuse;
        setRgb(out, x, y, isFinite(c) ? c : vec3(0.0f));
      }
  });
  return out;
}

}  // namespace holo::reference
