// The panorama's sun as a directional light (panorama_sun.hpp, reflect/src/sun_light.hpp): found
// from the pixels with its direction and power; on a Lambert sphere lit from behind and to the
// side it gives the closed form's crescent (the panorama's irradiance summed pixel by pixel),
// where the sun left in the 9 coefficients lights the whole face, and so through glass on a part
// inside it (inside_glass.hpp); a panorama without a sun or a relic with nothing diffuse casts
// none of its rays (counters). The real panoramas of ../shared/data: the park has a sun, the
// interior none.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "holo/core/equirect.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/panorama_sun.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"
#include "holo/sim/museum.hpp"
#include "inside_glass.hpp"
#include "reflect_test_scenes.hpp"
#include "shared_data.hpp"

namespace holo::reflect {
namespace {

const vec3 kSunDirection = glm::normalize(vec3(0.8f, 0.35f, -0.5f));  // behind the view, to its right

// A blue sky over a brown ground; with `sun`, the pixels within 1.5 degrees of kSunDirection hold
// `sun_radiance` more.
cv::Mat sunPanorama(int w, int h, bool sun, float sun_radiance = 3000.0f) {
  cv::Mat pano(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const vec3 d = equirect::uvToDirection({(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)});
      vec3 rgb = d.y > 0.0f ? vec3(0.3f, 0.38f, 0.55f) : vec3(0.16f, 0.13f, 0.1f);
      if (sun && glm::dot(d, kSunDirection) > std::cos(glm::radians(1.5f))) rgb += vec3(sun_radiance);
      pano.at<cv::Vec3f>(y, x) = cv::Vec3f(rgb.z, rgb.y, rgb.x);
    }
  return pano;
}

// The panorama's irradiance at `n`, summed over every pixel (its pixel-constant radiance).
vec3 exactIrradiance(const Environment& env, const vec3& n) {
  const cv::Mat& pano = env.panorama();
  vec3 e(0.0f);
  for (int y = 0; y < pano.rows; ++y) {
    const float omega = float(Environment::pixelSolidAngle(y, pano.cols, pano.rows));
    for (int x = 0; x < pano.cols; ++x) {
      const vec3 d = equirect::uvToDirection(
          {(float(x) + 0.5f) / float(pano.cols), (float(y) + 0.5f) / float(pano.rows)});
      e += rgbAt(pano, x, y) * omega * std::max(glm::dot(n, d), 0.0f);
    }
  }
  return e;
}

Model lambertSphere() {
  Model relic = relics::makeRelic("sphere");
  for (Material& m : relic.materials) {
    m.base_colour = vec3(0.8f);
    m.metallic = 0.0f;
    m.roughness = 1.0f;
    m.specular = 0.0f;
    m.base_colour_texture = {};
    m.metallic_roughness_texture = {};
  }
  return relic;
}

CameraModel frontView(const Bounds3& b, int size) {
  const vec3 target = b.center();
  const vec3 eye = target + vec3(0.0f, 0.0f, 2.5f * b.extent().y);
  return lookAtCamera(eye, target, framingFovDeg(eye, b), size, size);
}

TEST(PanoramaSun, FindsTheSunItsDirectionAndPower) {
  const Environment env(sunPanorama(256, 128, true));
  const PanoramaSun sun = findPanoramaSun(env);
  ASSERT_TRUE(sun.found) << sun.describe();
  EXPECT_GT(glm::dot(sun.direction, kSunDirection), std::cos(glm::radians(1.0f))) << sun.describe();
  // The power is the excess over the sky: 3000 over the disc's solid angle.
  const float disc = 2.0f * kPi * (1.0f - std::cos(glm::radians(1.5f)));
  EXPECT_NEAR(sun.power.x / (3000.0f * disc), 1.0f, 0.25f) << sun.describe();
  EXPECT_GT(sun.share, 0.5f);
  // Its lobe holds its power: the lobe over the sphere of directions integrates to it.
  for (float roughness : {0.3f, 0.7f}) {
    vec3 sum(0.0f);
    const int w = 512, h = 256;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        sum += sun.lobe(equirect::uvToDirection({(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)}),
                        roughness) *
               float(Environment::pixelSolidAngle(y, w, h));
    EXPECT_NEAR(sum.x / sun.power.x, 1.0f, 0.02f) << roughness;
  }
  const PanoramaSun none = findPanoramaSun(Environment(sunPanorama(256, 128, false)));
  EXPECT_FALSE(none.found) << none.describe();
}

// The crescent: over the sphere's pixels, ours against the closed form (albedo / pi times the
// panorama's exact irradiance at the normal), with the sun light and without it.
TEST(SunLight, LambertSphereShowsTheClosedFormsCrescentAndWorsensWithoutIt) {
  const Environment env(sunPanorama(256, 128, true));
  const PrefilteredIbl ibl(env, PrefilterOptions{6, 32, 16});
  ASSERT_TRUE(ibl.sun().found);
  const RenderScene scene(lambertSphere(), {});
  const CameraModel view = frontView(scene.relicBounds(), 40);
  const auto error = [&](bool sun_light, std::uint64_t* rays) {
    TracerSettings settings;
    settings.evaluation.sun_light = sun_light;
    settings.aa_samples = 1;
    settings.edge_aa = false;
    FrameRenderer renderer(scene, ibl, settings);
    const FrameResult r = renderer.render({}, {}, {view});
    EXPECT_EQ(r.plan.sun_light, sun_light) << r.plan.describe();
    if (rays) *rays = r.views.at(0).sun_rays;
    double sum = 0.0, truth_sum = 0.0;
    for (int y = 0; y < view.height(); ++y)
      for (int x = 0; x < view.width(); ++x) {
        HitPoint hp;
        if (!traceHitPoint(scene, view, vec2(float(x), float(y)), hp)) continue;
        const float truth = luminance(0.8f / kPi * exactIrradiance(env, hp.normal));
        sum += std::abs(double(luminance(rgbAt(r.views.at(0).hdr, x, y))) - double(truth));
        truth_sum += double(truth);
      }
    return sum / truth_sum;
  };
  std::uint64_t rays = 0;
  const double with = error(true, &rays), without = error(false, nullptr);
  std::printf(
      "Lambert sphere under a sun from behind: %.4f relative error with the sun light, %.4f without\n", with,
      without);
  EXPECT_GT(rays, 0u);
  EXPECT_LT(with, 0.05);
  EXPECT_GT(without, 2.0 * with);
}

TEST(SunLight, NoSunOrNothingDiffuseCastsNoRays) {
  const PrefilteredIbl sunny(Environment(sunPanorama(128, 64, true)), PrefilterOptions{6, 32, 16});
  const PrefilteredIbl overcast(Environment(sunPanorama(128, 64, false)), PrefilterOptions{6, 32, 16});
  const RenderScene lambert(lambertSphere(), {});
  const RenderScene glass(relics::makeRelic("glass-vase"), {});
  const auto sunRays = [&](const RenderScene& scene, const PrefilteredIbl& ibl, bool* planned) {
    FrameRenderer renderer(scene, ibl);
    const FrameResult r = renderer.render({}, {}, {frontView(scene.relicBounds(), 24)});
    *planned = r.plan.sun_light;
    return r.views.at(0).sun_rays;
  };
  bool planned = false;
  EXPECT_GT(sunRays(lambert, sunny, &planned), 0u);
  EXPECT_TRUE(planned);
  EXPECT_EQ(sunRays(lambert, overcast, &planned), 0u);
  EXPECT_FALSE(planned);
  EXPECT_EQ(sunRays(glass, sunny, &planned), 0u);
  EXPECT_FALSE(planned);
}

// What stands inside the glass (inside_glass.hpp): a Lambert ball sealed in a clear, tinted glass
// ball of IOR 1 (nothing bent or reflected, so the closed form is the tint times the open ball's)
// under the sun from behind. With the sun light the part inside shows the crescent through the
// glass; with the sun in the 9 coefficients it lights the whole face.
TEST(SunLight, APartInsideGlassShowsTheSunsCrescentThroughIt) {
  const Environment env(sunPanorama(256, 128, true));
  const PrefilteredIbl ibl(env, PrefilterOptions{6, 32, 16});
  ASSERT_TRUE(ibl.sun().found);
  const vec3 tint(1.0f, 0.7f, 0.4f);
  const RenderScene part(lambertSphere(), {});
  const Bounds3 bounds = part.relicBounds();
  Model model = lambertSphere();
  Model glass = test::sphereModel({tint, 0.0f, 0.0f, 1.0f}, glm::length(bounds.extent()), bounds.center());
  glass.materials[0].transmission = 1.0f;
  glass.materials[0].ior = 1.0f;
  glass.materials[0].thickness = 0.1f;
  glass.meshes[0].material = int(model.materials.size());
  model.meshes.push_back(glass.meshes[0]);
  model.materials.push_back(glass.materials[0]);
  const RenderScene scene(model, {});
  const CameraModel view = frontView(bounds, 24);
  const auto error = [&](bool sun_light) {
    TracerSettings settings;
    settings.evaluation.sun_light = sun_light;
    double sum = 0.0, truth_sum = 0.0;
    for (int y = 0; y < view.height(); ++y)
      for (int x = 0; x < view.width(); ++x) {
        const Ray ray = primaryRay(view, vec2(float(x), float(y)));
        const RayHit hit = part.relicOnly().intersect(ray);
        if (!hit.hit()) continue;
        const SurfacePoint surface = resolveSurface(part, part.relicOnly(), ray, hit, 0.0f);
        const vec3 ours = shadeInsideGlass(scene, ibl, settings, surface, ray.direction).shading.diffuse;
        const vec3 truth = tint * 0.8f / kPi * exactIrradiance(env, surface.normal);
        for (int c = 0; c < 3; ++c) {
          sum += std::abs(double(ours[c]) - double(truth[c]));
          truth_sum += double(truth[c]);
        }
      }
    return sum / truth_sum;
  };
  const double with = error(true), without = error(false);
  std::printf(
      "Lambert ball inside tinted glass under a sun from behind: %.4f relative error with the sun "
      "light, %.4f without\n",
      with, without);
  EXPECT_LT(with, 0.05);
  EXPECT_GT(without, 2.0 * with);
}

// The detection on the real panoramas: the park's sun, no sun in the interior (the others of
// ../shared/data printed for docs/materials.md).
TEST(PanoramaSun, TheParkHasASunTheInteriorNone) {
  HOLO_REQUIRE_SHARED_DATA("hdri/rooitou_park_1k.hdr");
  HOLO_REQUIRE_SHARED_DATA("hdri/st_fagans_interior_1k.hdr");
  const auto find = [](const std::string& name) {
    const PanoramaSun sun = findPanoramaSun(Environment(loadHdr(test::sharedData(name)).pixels));
    std::printf("%s: %s\n", name.c_str(), sun.describe().c_str());
    return sun;
  };
  EXPECT_TRUE(find("hdri/rooitou_park_1k.hdr").found);
  EXPECT_FALSE(find("hdri/st_fagans_interior_1k.hdr").found);
  for (const char* other : {"hdri/empty_warehouse_01_1k.hdr", "hdri/lebombo_1k.hdr",
                            "hdri/studio_small_03_1k.hdr", "hdri/blender_studio_dwab.exr"})
    if (std::filesystem::exists(test::sharedData(other))) find(other);
}

// The simulated halls' own panoramas, rendered as the live loop renders them: lamps and windows
// too wide or too weak to be a sun, so a museum frame pays nothing for the sun light.
TEST(PanoramaSun, TheSimulatedHallsHaveNone) {
  for (const char* hall : {"museum", "room", "atrium", "window"}) {
    const sim::Museum museum(sim::loadScene(hall));
    const PanoramaSun sun = findPanoramaSun(Environment(museum.renderPanorama(512, 256)));
    std::printf("%s: %s\n", hall, sun.describe().c_str());
    EXPECT_FALSE(sun.found) << hall;
  }
}

}  // namespace
}  // namespace holo::reflect
