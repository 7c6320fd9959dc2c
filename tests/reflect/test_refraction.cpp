// The live renderer's refraction pass and clearcoat (reflect/src/refraction_pass.hpp) and the
// effect plan's material passes: closed forms computed here (Fresnel at normal incidence, the
// slab's series, Snell through parallel faces, the white furnace), never the pass's own code,
// and the stability cases of issue 18.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "glass_transport.hpp"
#include "holo/core/equirect.hpp"
#include "holo/core/fibonacci_sphere.hpp"
#include "holo/core/image.hpp"
#include "holo/core/shapes.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/optics.hpp"
#include "holo/reflect/view.hpp"
#include "internal_depth.hpp"
#include "reflect_test_scenes.hpp"
#include "refraction_anchors.hpp"
#include "relic_passage.hpp"

namespace holo::reflect {
namespace {

using reference::PathTracer;
using reference::renderPathTraced;

// A glass sphere of radius 0.15 at (0, 0.3, 0).
Model glassSphere(float ior, float roughness = 0.0f, float thickness = 0.1f,
                  vec3 attenuation_colour = vec3(1.0f),
                  float attenuation_distance = std::numeric_limits<float>::infinity()) {
  Model model = test::sphereModel({vec3(1.0f), 0.0f, roughness, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f), 32, 64);
  Material& m = model.materials[0];
  m.transmission = 1.0f;
  m.ior = ior;
  m.thickness = thickness;
  m.attenuation_colour = attenuation_colour;
  m.attenuation_distance = attenuation_distance;
  return model;
}

// Clear smooth glass (white, fully transmissive) of index `ior` and glTF thickness `thickness` (m).
Material clearGlass(float ior, float thickness) {
  Material glass;
  glass.base_colour = vec3(1.0f);
  glass.transmission = 1.0f;
  glass.roughness = 0.0f;
  glass.ior = ior;
  glass.thickness = thickness;
  return glass;
}

// A closed box slab: |x|, |y| <= 1, |z| <= half_thickness, flat faces (no vertex normals).
Model slab(float half_thickness, const Material& material) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.positions.push_back(
        vec3((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? half_thickness : -half_thickness));
  const unsigned faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& f : faces) {
    mesh.triangles.push_back({f[0], f[1], f[2]});
    mesh.triangles.push_back({f[0], f[2], f[3]});
  }
  Model model;
  model.meshes.push_back(mesh);
  model.materials.push_back(material);
  return model;
}

// A panorama whose radiance is f(direction), 256 x 128.
template <class F>
Environment panorama(F&& f) {
  cv::Mat image(128, 256, CV_32FC3);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const vec3 d = equirect::uvToDirection(vec2((float(x) + 0.5f) / 256.0f, (float(y) + 0.5f) / 128.0f));
      setRgb(image, x, y, f(d));
    }
  return Environment(image);
}

TracerSettings staticOnly() {
  TracerSettings s = test::smallGrid();
  s.foreground_enabled = false;
  s.aa_samples = 1;
  s.exposure = 1.0f;
  return s;
}

ViewImages renderOnce(const RenderScene& scene, const PrefilteredIbl& ibl, const TracerSettings& settings,
                      const CameraModel& view, EffectPlan* plan = nullptr) {
  FrameRenderer renderer(scene, ibl, settings);
  FrameResult result = renderer.render({}, {}, {view});
  if (plan) *plan = result.plan;
  return result.views.at(0);
}

TEST(Refraction, FresnelClosedFormsAndRange) {
  for (float n : {1.0f, 1.0001f, 1.5f, 2.42f, 3.0f}) {
    const float r = (n - 1.0f) / (n + 1.0f);
    EXPECT_NEAR(fresnelDielectric(1.0f, n), r * r, 1e-6f) << n;
    EXPECT_NEAR(fresnelDielectric(1.0f, 1.0f / n), r * r, 1e-6f) << n;
    // Beyond the critical angle from inside: total reflection.
    if (n > 1.01f) {
      const float cos_critical = std::sqrt(1.0f - 1.0f / (n * n));
      EXPECT_EQ(fresnelDielectric(cos_critical * 0.99f, 1.0f / n), 1.0f) << n;
      EXPECT_LT(fresnelDielectric(std::min(cos_critical * 1.01f, 1.0f), 1.0f / n), 1.0f) << n;
    }
    for (float c : {0.0f, 1e-7f, 0.01f, 0.5f, 1.0f}) {
      const float f = fresnelDielectric(c, n);
      EXPECT_TRUE(f >= 0.0f && f <= 1.0f) << n << " " << c;
    }
  }
  EXPECT_NEAR(fresnelDielectric(0.3f, 1.0f), 0.0f, 1e-7f);  // no interface, no reflection
  EXPECT_EQ(fresnelDielectric(0.0f, 1.5f), 1.0f);           // grazing
  for (float bad : {std::nanf(""), -1.0f, 0.0f, std::numeric_limits<float>::infinity()}) {
    const float f = fresnelDielectric(0.5f, bad);
    EXPECT_TRUE(f >= 0.0f && f <= 1.0f);
  }
}

// A zero attenuation component (optics.hpp) absorbs its channel after any distance > 0, in the
// live glass as in the path tracer's; its coefficient stays finite, so a distance of 0 leaves the
// light as it is rather than NaN.
TEST(Refraction, AZeroAttenuationComponentAbsorbsItsChannel) {
  const vec3 sigma = attenuationCoefficient(vec3(0.5f, 1.0f, 0.0f), 0.1f);
  EXPECT_FLOAT_EQ(sigma.r, -std::log(0.5f) / 0.1f);
  EXPECT_EQ(sigma.g, 0.0f);
  EXPECT_EQ(sigma.b, kOpaqueAbsorption);
  EXPECT_EQ(transmittance(sigma, 0.0f), vec3(1.0f));
  const vec3 short_way = transmittance(sigma, 1e-6f);
  EXPECT_EQ(short_way.b, 0.0f);
  EXPECT_EQ(short_way.g, 1.0f);
  EXPECT_GT(short_way.r, 0.99f);
  EXPECT_EQ(attenuationCoefficient(vec3(0.0f), std::numeric_limits<float>::infinity()), vec3(0.0f));
  // Through a slab 0.1 thick: no blue leaves it, nor is any sent back from inside.
  Material glass = clearGlass(1.5f, 0.1f);
  glass.attenuation_colour = vec3(0.5f, 1.0f, 0.0f);
  glass.attenuation_distance = 0.1f;
  const RenderScene scene(slab(0.05f, glass), {});
  const PrefilteredIbl ibl(Environment::uniform(vec3(1.0f)), PrefilterOptions{3, 16, 8});
  const TransmittedPath path = traceTransmission(scene, ibl, TracerSettings{}, 8, vec3(0.0f, 0.0f, 0.05f),
                                                 vec3(0, 0, 1), vec3(0, 0, -1), glass);
  ASSERT_TRUE(path.exited);
  EXPECT_EQ(path.scale.b, 0.0f);
  EXPECT_EQ(path.resolved.b, 0.0f);
  EXPECT_EQ(path.reflected.b, 0.0f);
  // Red and green leave as through any slab: (1 - R)^2 a, R = 0.04 at normal incidence (and at most
  // the share R^2 a^2 more where the light reflected inside is summed as between parallel walls).
  EXPECT_NEAR(path.scale.r, 0.96f * 0.96f * 0.5f, 1e-3f);
  EXPECT_NEAR(path.scale.g, 0.96f * 0.96f, 2e-3f);
  EXPECT_TRUE(isFinite(path.scale) && isFinite(path.resolved) && isFinite(path.reflected));
}

// Through a slab's two parallel faces a ray leaves in the direction it came in (Snell both ways),
// at any angle below grazing; a thin-walled one is not bent at all.
TEST(Refraction, ParallelFacesGiveBackTheDirectionAndThinWallsDoNotBend) {
  Material glass;
  glass.transmission = 1.0f;
  glass.roughness = 0.0f;
  glass.ior = 1.5f;
  glass.thickness = 0.05f;
  const RenderScene scene(slab(0.05f, glass), {});
  const PrefilteredIbl ibl(Environment::uniform(vec3(1.0f)), PrefilterOptions{3, 16, 8});
  TracerSettings settings;
  for (float degrees : {0.0f, 30.0f, 60.0f, 85.0f}) {
    const float a = degrees * kPi / 180.0f;
    const vec3 d(std::sin(a), 0.0f, -std::cos(a));
    const TransmittedPath path =
        traceTransmission(scene, ibl, settings, 8, vec3(0.0f, 0.0f, 0.05f), vec3(0, 0, 1), d, glass);
    ASSERT_TRUE(path.exited) << degrees;
    EXPECT_GT(glm::dot(path.exit_direction, d), 1.0f - 1e-5f) << degrees;
    EXPECT_LT(path.exit_position.z, -0.05f) << degrees;
    // Sideways shift through the slab: thickness tan(refraction angle), Snell's sine law.
    const float sin_t = std::sin(a) / 1.5f, tan_t = sin_t / std::sqrt(1.0f - sin_t * sin_t);
    EXPECT_NEAR(path.exit_position.x, 0.1f * tan_t, 2e-3f) << degrees;
    EXPECT_EQ(path.events, 2);
  }
  Material thin = glass;
  thin.thickness = 0.0f;
  const RenderScene thin_scene(slab(0.05f, thin), {});
  const vec3 d = glm::normalize(vec3(0.5f, 0.0f, -1.0f));
  const TransmittedPath path =
      traceTransmission(thin_scene, ibl, settings, 8, vec3(0.0f, 0.0f, 0.05f), vec3(0, 0, 1), d, thin);
  ASSERT_TRUE(path.exited);
  EXPECT_EQ(path.events, 2);  // both walls crossed
  EXPECT_GT(glm::dot(path.exit_direction, d), 1.0f - 1e-6f);
}

// A slab at normal incidence, the environment 1 behind it and 0 in front: it transmits
// (1-R)^2 a / (1 - R^2 a^2), R = ((n-1)/(n+1))^2, a = exp(-sigma d).
TEST(Refraction, SlabAtNormalIncidenceTransmitsTheSeriesOfItsReflections) {
  const Environment env = panorama([](const vec3& d) { return vec3(std::max(0.0f, -d.z)); });
  const PrefilteredIbl ibl(env, PrefilterOptions{3, 256, 8});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.0f, 3.0f), vec3(0.0f), 2.0f, 9, 9);
  for (float n : {1.0f, 1.5f, 2.42f, 3.0f}) {
    for (float a : {1.0f, 0.5f}) {
      Material glass = clearGlass(n, 0.1f);
      if (a < 1.0f) {
        glass.attenuation_colour = vec3(a);
        glass.attenuation_distance = 0.1f;  // the slab's thickness: one crossing attenuates by a
      }
      const RenderScene scene(slab(0.05f, glass), {});
      const ViewImages v = renderOnce(scene, ibl, staticOnly(), view);
      const float r = ((n - 1.0f) / (n + 1.0f)) * ((n - 1.0f) / (n + 1.0f));
      const float expected = (1.0f - r) * (1.0f - r) * a / (1.0f - r * r * a * a);
      const vec3 c = rgbAt(v.hdr, 4, 4);
      EXPECT_NEAR(c.g, expected, 0.003f) << "n " << n << " a " << a;
      EXPECT_NEAR(c.r, c.b, 1e-5f);
      EXPECT_GT(v.refraction_rays, 0u);
    }
  }
}

// IOR 1, no absorption: the glass disappears, every pixel shows the environment behind it.
TEST(Refraction, IorOneShowsTheEnvironmentBehindUnchanged) {
  const auto sky = [](const vec3& d) {
    return vec3(1.0f + 0.5f * d.x, 1.0f + 0.3f * d.y, 1.0f - 0.4f * d.z);
  };
  const PrefilteredIbl ibl(panorama(sky), PrefilterOptions{3, 256, 8});
  const RenderScene scene(glassSphere(1.0f), {});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 20.0f, 32, 32);
  const ViewImages v = renderOnce(scene, ibl, staticOnly(), view);
  int checked = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      if (v.coverage.at<float>(y, x) < 1.0f) continue;
      const vec3 expected = sky(primaryRay(view, vec2(x, y)).direction);
      const vec3 c = rgbAt(v.hdr, x, y);
      ASSERT_LT(glm::length(c - expected), 0.01f * glm::length(expected)) << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, 300);
}

// A white furnace: non-absorbing clear glass in a uniform environment of 1 reflects plus
// transmits exactly what arrives, whatever its IOR, depth cap or wall: never lost or invented.
TEST(Refraction, WhiteFurnaceKeepsEnergyAtEveryIorAndCap) {
  const PrefilteredIbl ibl(Environment::uniform(vec3(1.0f)), PrefilterOptions{3, 32, 8});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 20.0f, 24, 24);
  for (float n : {1.0f, 1.0001f, 1.5f, 2.42f, 3.0f}) {
    for (int depth : {1, 2, 32}) {
      for (float thickness : {0.1f, 0.0f}) {
        const RenderScene scene(glassSphere(n, 0.0f, thickness), {});
        TracerSettings settings = staticOnly();
        settings.refraction_depth = depth;
        const ViewImages v = renderOnce(scene, ibl, settings, view);
        for (int y = 0; y < 24; ++y)
          for (int x = 0; x < 24; ++x) {
            if (v.coverage.at<float>(y, x) < 1.0f) continue;
            const vec3 c = rgbAt(v.hdr, x, y);
            ASSERT_NEAR(c.g, 1.0f, 0.01f)
                << "ior " << n << " depth " << depth << " thickness " << thickness << " at " << x << "," << y;
          }
        if (depth == 1 && thickness > 0.0f) {
          EXPECT_GT(v.capped_paths, 0u);
        }
      }
    }
  }
}

// The stability cases of issue 18: every pixel finite and within the environment's range.
TEST(Refraction, StabilityCasesStayFiniteAndInRange) {
  const auto sky = [](const vec3& d) {
    return vec3(0.5f + 0.5f * std::max(d.y, 0.0f), 0.4f, 0.3f + 0.2f * d.x);
  };
  const PrefilteredIbl ibl(panorama(sky), PrefilterOptions{4, 64, 8});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 20.0f, 24, 24);
  const float huge = 1e30f;
  struct Case {
    const char* name;
    Model model;
    int depth;
  };
  std::vector<Case> cases;
  for (float n : {1.0f, 1.0001f, 2.42f, 3.0f}) cases.push_back({"ior", glassSphere(n), 0});
  cases.push_back({"trapped by total internal reflection (cap 3)", glassSphere(3.0f), 3});
  cases.push_back({"transmission roughness 0", glassSphere(1.5f, 0.0f), 0});
  cases.push_back({"transmission roughness 1", glassSphere(1.5f, 1.0f), 0});
  cases.push_back(
      {"attenuationDistance 1e-6", glassSphere(1.5f, 0.0f, 0.1f, vec3(0.5f, 0.8f, 0.0f), 1e-6f), 0});
  cases.push_back({"attenuationDistance huge", glassSphere(1.5f, 0.0f, 0.1f, vec3(0.5f), huge), 0});
  cases.push_back({"thickness 0", glassSphere(1.5f, 0.3f, 0.0f), 0});
  for (const Case& c : cases) {
    const RenderScene scene(c.model, {});
    TracerSettings settings = staticOnly();
    settings.refraction_depth = c.depth;
    settings.aa_samples = 4;  // grazing samples at the silhouette too
    settings.exposure = 0.0f;
    const ViewImages v = renderOnce(scene, ibl, settings, view);
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) {
        const vec3 p = rgbAt(v.hdr, x, y);
        ASSERT_TRUE(isFinite(p)) << c.name;
        ASSERT_GE(glm::min(p.x, glm::min(p.y, p.z)), 0.0f) << c.name;
        ASSERT_LE(glm::max(p.x, glm::max(p.y, p.z)), 1.0f + 1e-3f) << c.name;  // the sky's maximum
      }
    EXPECT_GT(v.refracted_samples, 0u) << c.name;
  }
  // Grazing incidence straight into the path: finite, energy at most what arrived.
  const RenderScene scene(glassSphere(2.42f), {});
  const Material& m = scene.relic().materials[0];
  for (float cos_i : {1e-7f, 1e-3f, 0.05f}) {
    const vec3 n(0.0f, 0.0f, 1.0f), d(std::sqrt(1.0f - cos_i * cos_i), 0.0f, -cos_i);
    const TransmittedPath path =
        traceTransmission(scene, ibl, TracerSettings{}, 8, vec3(0.0f, 0.3f, 0.15f), n, d, m);
    EXPECT_TRUE(isFinite(path.scale) && isFinite(path.resolved) && isFinite(path.exit_direction));
    EXPECT_LE(path.scale.g, 1.0f);
  }
}

// Sparse paths: with a stride of 2 or 4 pixels between the traced paths the samples between blend
// their anchors where these agree and a refined pixel's sub-samples share one path; the image
// stays within a few percent of every sample tracing its own path, for a fraction of the rays,
// and renders the same twice.
TEST(Refraction, SparsePathsBlendTheAnchorsForAFractionOfTheRays) {
  const auto sky = [](const vec3& d) {
    return vec3(0.5f + 0.5f * std::max(d.y, 0.0f), 0.4f + 0.2f * d.z, 0.3f + 0.2f * d.x);
  };
  const PrefilteredIbl ibl(panorama(sky), PrefilterOptions{4, 64, 8});
  const RenderScene scene(glassSphere(1.5f), {});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 16.0f, 48, 48);
  const auto render = [&](int stride) {
    TracerSettings settings = staticOnly();
    settings.edge_aa = true;
    settings.refraction_stride = stride;
    return renderOnce(scene, ibl, settings, view);
  };
  const ViewImages every = render(1), two = render(2), four = render(4);
  EXPECT_EQ(two.refracted_samples, every.refracted_samples);
  EXPECT_EQ(four.refracted_samples, every.refracted_samples);
  EXPECT_LT(double(two.refraction_rays), 0.5 * double(every.refraction_rays));
  // Wider strides leave more samples between anchors that disagree: no fewer rays on this sphere.
  EXPECT_LT(four.refraction_rays, every.refraction_rays);
  for (const ViewImages* sparse : {&two, &four}) {
    double difference = 0.0, sum = 0.0;
    float largest = 0.0f;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 48; ++x) {
        if (every.coverage.at<float>(y, x) < 1.0f) continue;
        const vec3 a = rgbAt(every.hdr, x, y), b = rgbAt(sparse->hdr, x, y);
        difference += glm::length(a - b);
        sum += glm::length(a);
        largest = std::max(largest, glm::length(a - b) / glm::length(a));
      }
    EXPECT_LT(difference / sum, 0.02) << "mean relative difference";
    EXPECT_LT(largest, 0.2f) << "largest relative difference of a pixel";
  }
  const ViewImages again = render(2);
  EXPECT_EQ(cv::norm(two.hdr, again.hdr, cv::NORM_INF), 0.0);
}

// A refined pixel on the anchor lattice: the sub-sample its anchor was traced from takes the
// anchor's path instead of tracing it again. The path handed over must be that sample's own (the
// same trace, bit for bit), and no other sample (another sub-sample, an anchor that blended
// rather than traced) may be handed an anchor's path.
TEST(Refraction, ARefinedAnchorPixelsSampleTakesThePathItsAnchorTraced) {
  const PrefilteredIbl ibl(panorama([](const vec3& d) { return vec3(0.5f + 0.5f * std::max(d.y, 0.0f)); }),
                           PrefilterOptions{4, 64, 8});
  const RenderScene scene(glassSphere(1.5f), {});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 16.0f, 48, 48);
  const TracerSettings settings = staticOnly();
  HitPointBuffer hits;
  traceHitPoints(scene, view, AntiAliasing::Edges, hits);
  const AnchorGrid grid = anchorGrid(hits, 2);
  std::vector<RefractionAnchor> anchors;
  traceAnchors(scene, ibl, settings, 4, hits, grid, anchors);
  int handed = 0, refused = 0;
  for (const std::size_t p : hits.covered) {
    if (hits.sampleCount(p) != 4) continue;
    for (std::size_t i = hits.firstSample(p); i < hits.firstSample(p) + 4; ++i) {
      const RefractionAnchor* own = anchorTracedAt(anchors, grid, hits, p, i);
      if (!own) {
        ++refused;
        continue;
      }
      ++handed;
      ASSERT_TRUE(hits.valid[i]);
      EXPECT_EQ(own->source.anchors, 0) << "a blended anchor's path is no sample's own";
      const HitPoint& hp = hits.hits[i];
      const TransmittedPath fresh = traceTransmissionPerUnitEntry(
          scene, ibl, settings, 4, hp.position, hp.normal, -hp.to_viewer, *hp.gltf, &hp.material, nullptr);
      EXPECT_EQ(own->unit.exit_direction, fresh.exit_direction);
      EXPECT_EQ(own->unit.exit_position, fresh.exit_position);
      EXPECT_EQ(own->unit.scale, fresh.scale);
      EXPECT_EQ(own->unit.events, fresh.events);
      EXPECT_EQ(own->unit.rays, fresh.rays);
    }
  }
  EXPECT_GT(handed, 0) << "the sphere's silhouette has refined pixels on the lattice";
  EXPECT_GT(refused, 3 * handed) << "at most one sub-sample of a pixel is its anchor's";
}

// The plan: an opaque relic runs no material pass and traces no refraction ray; glass does, with
// the depth measured on the relic and its reason in the statistics.
TEST(Refraction, OnlyATransmissiveRelicPaysForRefraction) {
  const PrefilteredIbl ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{3, 16, 8});
  const test::RedWall wall = test::redWall();
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 16.0f, 32, 32);
  {
    const RenderScene opaque(test::sphereModel({vec3(0.9f), 1.0f, 0.1f, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f)),
                             {});
    FrameRenderer renderer(opaque, ibl, test::smallGrid());
    const FrameResult r = renderer.render(wall.cloud, {wall.camera}, {view});
    EXPECT_TRUE(r.plan.has(Pass::ForegroundWalk)) << r.plan.describe();
    for (Pass p : {Pass::Refraction, Pass::RefractedForeground, Pass::Clearcoat})
      EXPECT_FALSE(r.plan.has(p)) << passName(p);
    EXPECT_EQ(r.plan.internal_depth, 0);
    EXPECT_NE(r.plan.describe().find("opaque relic"), std::string::npos) << r.plan.describe();
    const ViewImages& v = r.views.at(0);
    EXPECT_EQ(v.refraction_rays, 0u);
    EXPECT_EQ(v.refracted_samples, 0u);
    EXPECT_EQ(v.refracted_walks, 0u);
    EXPECT_EQ(v.supersampled_samples, 0u);
    EXPECT_EQ(v.coated_samples, 0u);
    for (const PassTiming& t : v.timings) EXPECT_NE(t.pass, Pass::Refraction);
  }
  const RenderScene glass(glassSphere(1.5f), {});
  FrameRenderer renderer(glass, ibl, test::smallGrid());
  const FrameResult r = renderer.render(wall.cloud, {wall.camera}, {view});
  for (Pass p : {Pass::Refraction, Pass::RefractedForeground}) EXPECT_TRUE(r.plan.has(p)) << passName(p);
  EXPECT_FALSE(r.plan.has(Pass::Clearcoat));
  EXPECT_NE(r.plan.describe().find("measured"), std::string::npos) << r.plan.describe();
  // A sphere: in, out; a few paths reflect totally once or twice more.
  EXPECT_GE(r.plan.internal_depth, 2);
  EXPECT_LE(r.plan.internal_depth, 8);
  const ViewImages& v = r.views.at(0);
  EXPECT_GT(v.refraction_rays, 0u);
  EXPECT_GT(v.refracted_samples, 0u);
  EXPECT_GT(v.refracted_walks, 0u);
  // Switched off, the glass is shaded as opaque (the comparison's "before"): no refraction work.
  TracerSettings off = test::smallGrid();
  off.evaluation.refraction_enabled = false;
  FrameRenderer opaque_glass(glass, ibl, off);
  const FrameResult o = opaque_glass.render(wall.cloud, {wall.camera}, {view});
  EXPECT_FALSE(o.plan.has(Pass::Refraction)) << o.plan.describe();
  EXPECT_EQ(o.views.at(0).refraction_rays, 0u);
  // Refraction of the IBL only: traced, but no exit ray walks.
  TracerSettings ibl_only = test::smallGrid();
  ibl_only.evaluation.refracted_foreground = false;
  FrameRenderer no_visitors(glass, ibl, ibl_only);
  const FrameResult n = no_visitors.render(wall.cloud, {wall.camera}, {view});
  EXPECT_TRUE(n.plan.has(Pass::Refraction));
  EXPECT_FALSE(n.plan.has(Pass::RefractedForeground));
  EXPECT_GT(n.views.at(0).refraction_rays, 0u);
  EXPECT_EQ(n.views.at(0).refracted_walks, 0u);
}

// A visitor behind clear glass is seen through it: the red wall of test::redWall() seen from the
// other side of a glass sphere, along the axis (no bending): red 2 x (1-R)/(1+R), R the head-on
// reflectance (the slab's series for one crossing in and out); IOR 1: red 2 exactly. The same
// where each sample is the mean of 16 paths, the visitors walked along each (supersampling at
// every difference); at the default contrast the smooth sphere supersamples nothing.
TEST(Refraction, TheVisitorBehindTheGlassIsSeenThroughIt) {
  const PrefilteredIbl ibl(Environment::uniform(vec3(0.5f)), PrefilterOptions{3, 16, 8});
  const test::RedWall wall = test::redWall();
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, -1.2f), vec3(0.0f, 0.3f, 0.0f), 16.0f, 33, 33);
  for (float n : {1.0f, 1.5f})
    for (const bool supersampled : {false, true}) {
      const RenderScene glass(glassSphere(n), {});
      TracerSettings settings = test::smallGrid();
      if (supersampled) {  // every pixel four samples, and each of them 16 paths wherever these differ
        settings.aa_samples = 4;
        settings.refraction_supersample_contrast = 1.0f;
      }
      FrameRenderer renderer(glass, ibl, settings);
      const FrameResult r = renderer.render(wall.cloud, {wall.camera}, {view});
      ASSERT_TRUE(r.plan.has(Pass::RefractedForeground)) << r.plan.describe();
      const ViewImages& v = r.views.at(0);
      const float reflectance = ((n - 1.0f) / (n + 1.0f)) * ((n - 1.0f) / (n + 1.0f));
      const vec3 c = rgbAt(v.hdr, 16, 16);
      // What does not get through, 2R/(1+R), is reflected back to the viewer's side: the grey hall.
      const float through = (1.0f - reflectance) / (1.0f + reflectance), back = 1.0f - through;
      EXPECT_NEAR(c.r, 2.0f * through + 0.5f * back, 0.05f) << n << " " << supersampled;
      EXPECT_NEAR(c.g, 0.5f * back, 0.002f) << n << " " << supersampled;
      EXPECT_GT(v.refracted_walks, 0u);
      if (supersampled && n > 1.0f) {
        EXPECT_GT(v.supersampled_samples, 100u);
      } else if (!supersampled) {
        EXPECT_EQ(v.supersampled_samples, 0u);
      }
    }
}

// The measured depth: a sphere needs its two interfaces (inside, light meets the surface at its
// refraction angle, below the critical one: never totally reflected); a high-index cube traps
// light by total internal reflection (a face next to the entry one is met beyond the critical
// angle) and needs more; the residual at the chosen depth is below the limit and at
// one event less it is not.
TEST(Refraction, InternalDepthIsTheSmallestThatLeavesLessThanTheLimit) {
  const PrefilteredIbl ibl(Environment::uniform(vec3(1.0f)), PrefilterOptions{3, 16, 8});
  TracerSettings settings;
  const RenderScene sphere(glassSphere(1.5f), {});
  const InternalDepth d = measureInternalDepth(sphere, ibl, settings, 0.01f);
  EXPECT_GT(d.probes_hit, 100u);
  EXPECT_EQ(d.depth, 2);
  EXPECT_LT(d.residual, 0.01f);
  EXPECT_NEAR(d.left[1], 1.0, 1e-6);  // after entering, all of it is inside
  Material diamond;
  diamond.transmission = 1.0f;
  diamond.roughness = 0.0f;
  diamond.ior = 2.42f;
  diamond.thickness = 0.1f;
  const RenderScene cube(slab(1.0f, diamond), {});
  const InternalDepth deep = measureInternalDepth(cube, ibl, settings, 0.01f);
  EXPECT_GT(deep.depth, d.depth);
  EXPECT_LT(deep.residual, 0.01f);
  EXPECT_GE(deep.left[std::size_t(deep.depth - 1)], 0.01);
  for (std::size_t k = 1; k + 1 < deep.left.size(); ++k) EXPECT_LE(deep.left[k + 1], deep.left[k] + 1e-9);
}

// The depth follows the channel that stays: a diamond cube that absorbs red and green within a few
// of its widths keeps its blue light bouncing after the luminance is gone, and its depth is the clear
// cube's, where the luminance (72% green) alone would stop it early and send the blue light out
// along its last direction.
TEST(Refraction, InternalDepthFollowsTheChannelTheVolumeDoesNotAbsorb) {
  const PrefilteredIbl ibl(Environment::uniform(vec3(1.0f)), PrefilterOptions{3, 16, 8});
  TracerSettings settings;
  Material diamond;
  diamond.transmission = 1.0f;
  diamond.roughness = 0.0f;
  diamond.ior = 2.42f;
  diamond.thickness = 0.1f;
  const InternalDepth clear =
      measureInternalDepth(RenderScene(slab(1.0f, diamond), {}), ibl, settings, 0.01f);
  diamond.attenuation_colour = vec3(0.05f, 0.05f, 1.0f);
  diamond.attenuation_distance = 1.0f;
  const InternalDepth blue = measureInternalDepth(RenderScene(slab(1.0f, diamond), {}), ibl, settings, 0.01f);
  EXPECT_EQ(blue.depth, clear.depth);
  EXPECT_LT(blue.residual, 0.01f);
  EXPECT_GE(blue.left[std::size_t(blue.depth - 1)], 0.01);
}

// A sphere of radius 0.15 at (0, 0.3, 0) whose base is black and reflects nothing
// (SurfaceMaterial::specular 0), under a mirror clearcoat where `coated`: the override is the
// material at every hit, its coat included (as the path tracer reads it).
std::unique_ptr<RenderScene> blackSphere(bool coated) {
  SurfaceMaterial black{vec3(0.0f), 0.0f, 1.0f, 0.0f};
  black.clearcoat = coated ? 1.0f : 0.0f;
  black.clearcoat_roughness = 0.0f;
  Model model = test::sphereModel(black, 0.15f, vec3(0.0f, 0.3f, 0.0f));
  model.materials[0].clearcoat = black.clearcoat;
  model.materials[0].clearcoat_roughness = black.clearcoat_roughness;
  auto scene = std::make_unique<RenderScene>(model, std::vector<Model>{});
  scene->overrideRelicMaterial(black);
  return scene;
}

// Clearcoat: a second specular lobe. Over a black diffuse base in a uniform environment L the
// pixel is the coat's reflectance times L, about 0.04 head-on; without the coat, black.
TEST(Refraction, ClearcoatAddsASecondSpecularLobe) {
  const PrefilteredIbl ibl(Environment::uniform(vec3(1.0f)), PrefilterOptions{3, 16, 8});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.2f), vec3(0.0f, 0.3f, 0.0f), 20.0f, 24, 24);
  const std::unique_ptr<RenderScene> bare = blackSphere(false), coated = blackSphere(true);
  TracerSettings settings = staticOnly();
  EffectPlan plan;
  const ViewImages without = renderOnce(*bare, ibl, settings, view, &plan);
  EXPECT_FALSE(plan.has(Pass::Clearcoat));
  const ViewImages with = renderOnce(*coated, ibl, settings, view, &plan);
  EXPECT_TRUE(plan.has(Pass::Clearcoat));
  EXPECT_FALSE(plan.has(Pass::Refraction));
  EXPECT_EQ(with.refraction_rays, 0u);
  EXPECT_GT(with.coated_samples, 0u);
  EXPECT_LT(rgbAt(without.hdr, 12, 12).g, 1e-3f);
  EXPECT_NEAR(rgbAt(with.hdr, 12, 12).g, 0.04f, 0.01f);
}

// The coat sees the hall where the base's own reflection does: through the panorama's proxy
// (a hall 1.2 m around a capture point 0.5 m above the relic, PanoramaProxy). A mirror coat over a
// black base shows 0.04 of what a mirror metal sphere shows, pixel for pixel (head-on, where the
// coat's reflectance is 0.04), in a hall whose radiance changes fast with direction.
TEST(Refraction, TheClearcoatReadsTheHallThroughItsProxy) {
  PanoramaProxy proxy;
  proxy.centre = vec3(0.0f, 0.8f, 0.0f);
  proxy.radius = 1.2f;
  const Environment sky = panorama([](const vec3& d) {
    return vec3(0.1f) +
           vec3(2.0f, 1.0f, 0.5f) * std::pow(0.5f + 0.5f * std::sin(6.0f * d.x + 3.0f * d.y), 2.0f);
  });
  const PrefilteredIbl ibl(Environment(sky.panorama(), 0.0f, proxy), PrefilterOptions{4, 256, 8});
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.3f, 1.0f), vec3(0.0f, 0.3f, 0.0f), 20.0f, 32, 32);
  const std::unique_ptr<RenderScene> coated = blackSphere(true);
  RenderScene mirror(test::sphereModel({vec3(1.0f), 1.0f, 0.0f, 1.0f}, 0.15f, vec3(0.0f, 0.3f, 0.0f)), {});
  TracerSettings settings = staticOnly();
  const ViewImages coat = renderOnce(*coated, ibl, settings, view);
  const ViewImages metal = renderOnce(mirror, ibl, settings, view);
  double worst = 0.0;
  for (int y = 12; y < 20; ++y)
    for (int x = 12; x < 20; ++x)
      worst = std::max(worst, std::abs(double(rgbAt(coat.hdr, x, y).r / rgbAt(metal.hdr, x, y).r) - 0.04));
  EXPECT_LT(worst, 0.002);  // 0 measured; along the direction from the capture point, 0.34
}

// Mean absolute error of `image` against `truth` (sums of RGB) over the pixels lying wholly on
// the relic (all four corners hit it: no silhouette), relative to the truth's mean there;
// `pixels` counts them.
double errorOnTheRelic(const RenderScene& scene, const CameraModel& view, const cv::Mat& truth,
                       const cv::Mat& image, int& pixels) {
  double error_sum = 0.0, truth_sum = 0.0;
  pixels = 0;
  for (int y = 0; y < view.height(); ++y)
    for (int x = 0; x < view.width(); ++x) {
      bool inside = true;
      for (const vec2 corner : {vec2(-0.5f, -0.5f), vec2(0.5f, -0.5f), vec2(-0.5f, 0.5f), vec2(0.5f, 0.5f)})
        inside = inside && scene.relicOnly().intersect(primaryRay(view, vec2(x, y) + corner)).hit();
      if (!inside) continue;
      const vec3 t = rgbAt(truth, x, y), c = rgbAt(image, x, y);
      error_sum += std::abs(double(c.r + c.g + c.b) - double(t.r + t.g + t.b));
      truth_sum += double(t.r + t.g + t.b);
      ++pixels;
    }
  return truth_sum > 0.0 ? error_sum / truth_sum : 0.0;
}

// errorOnTheRelic of the live renderer with `settings` at four samples a pixel (the truth averages
// over the pixel: a facet's or a wall's edges cross many), on at least 90 such pixels.
double relicErrorAtFourSamples(const RenderScene& scene, const PrefilteredIbl& ibl, const CameraModel& view,
                               const cv::Mat& truth, TracerSettings settings) {
  settings.aa_samples = 4;
  const ViewImages v = renderOnce(scene, ibl, settings, view);
  int pixels = 0;
  const double relative = errorOnTheRelic(scene, view, truth, v.hdr, pixels);
  EXPECT_GT(pixels, 90);
  return relative;
}

// A triangular bipyramid: an equilateral girdle of circumradius r at `centre`, apexes h above and
// below it, flat faces (no vertex normals) wound counter-clockwise seen from outside. No two of its
// faces are parallel, so light reflected inside at an exit leaves through other faces, as in a
// cut gem.
Model bipyramid(float r, float h, const vec3& centre, const Material& material) {
  TriangleMesh mesh;
  const auto girdle = [&](int k) {
    const float a = 2.0f * kPi * float(k % 3) / 3.0f + 0.3f;
    return centre + vec3(r * std::cos(a), 0.0f, r * std::sin(a));
  };
  for (int k = 0; k < 3; ++k)
    for (float side : {1.0f, -1.0f}) {
      const auto base = static_cast<unsigned>(mesh.positions.size());
      mesh.positions.push_back(girdle(k));
      mesh.positions.push_back(girdle(k + 1));
      mesh.positions.push_back(centre + vec3(0.0f, side * h, 0.0f));
      const vec3 n = glm::cross(mesh.positions[base + 1] - mesh.positions[base],
                                mesh.positions[base + 2] - mesh.positions[base]);
      if (glm::dot(n, mesh.positions[base] - centre) > 0.0f)
        mesh.triangles.push_back({base, base + 1, base + 2});
      else
        mesh.triangles.push_back({base, base + 2, base + 1});
    }
  Model model;
  model.meshes.push_back(mesh);
  model.materials.push_back(material);
  return model;
}

// A clear, smooth, white diamond (IOR 2.42) cut as that bipyramid, 0.3 m wide at (0, 0.3, 0).
Model gem() {
  Material diamond;
  diamond.base_colour = vec3(1.0f);
  diamond.transmission = 1.0f;
  diamond.roughness = 0.0f;
  diamond.ior = 2.42f;
  diamond.thickness = 0.1f;
  return bipyramid(0.15f, 0.1f, vec3(0.0f, 0.3f, 0.0f), diamond);
}

// A diamond (IOR 2.42, near its critical angle of 24.4 degrees much of the light leaving is
// reflected inside) under a sky with one bright region: the live renderer follows the light
// reflected inside at each exit out through the other facets, as the path tracer does (1024
// samples per pixel): its mean absolute error over the pixels wholly on the gem is under 14% of
// the truth's mean (11.6% measured; the rest is mostly facet edges inside pixels); summed as
// between parallel walls (refraction_branch_rays 0) it is more than 1.4 times as large (19.4%).
// Every sample traces its own path (refraction_stride 1) but in the last check.
TEST(Refraction, LightReflectedInsideAGemLeavesThroughItsOtherFacets) {
  const RenderScene scene(gem(), {});
  const Environment sky = panorama([](const vec3& d) {
    const float sun = std::max(0.0f, glm::dot(d, glm::normalize(vec3(-0.6f, 0.5f, -0.3f))));
    return vec3(0.05f + 0.1f * std::max(d.y, 0.0f)) + vec3(2.0f, 1.6f, 1.2f) * std::pow(sun, 6.0f);
  });
  const PrefilteredIbl ibl(sky, PrefilterOptions{4, 256, 8});
  constexpr int kSize = 32;
  const CameraModel view = lookAtCamera(vec3(0.3f, 0.6f, 0.7f), vec3(0.0f, 0.3f, 0.0f), 30.0f, kSize, kSize);
  const PathTracer tracer(scene, sky);
  const cv::Mat truth = renderPathTraced(tracer, view, 1024);
  const auto error = [&](int branch_rays, int stride = 1) {
    TracerSettings settings = staticOnly();
    settings.refraction_branch_rays = branch_rays;
    settings.refraction_stride = stride;
    return relicErrorAtFourSamples(scene, ibl, view, truth, settings);
  };
  const double followed = error(TracerSettings{}.refraction_branch_rays), summed = error(0);
  EXPECT_LT(followed, 0.14);
  EXPECT_GT(summed, 1.4 * followed);
  // At the default stride, where the anchors around a sample meet another number of events
  // inside (a facet's edge), each sub-sample of the pixel traces its own path: within 1.6 times
  // the error of every sample tracing (1.43 measured); one path shared by the four, 3.2 times.
  EXPECT_LT(error(TracerSettings{}.refraction_branch_rays, TracerSettings{}.refraction_stride),
            1.6 * followed);
}

// A clear tumbler with thin walls (2 mm, IOR 1.5, tinted over 5 mm), open at the top, seen from
// the side under a blue sky over a dark ground: where the view ray crosses a wall obliquely its
// inner face reflects much of the light back into the wall, which guides it on round the curve and
// lets it out where it reaches, each exit seeing the sky along its own ray. At the default weight
// and budget (0.1, 8 rays) ordinary glass keeps the parallel-walls sum, which lets that light out
// at once; followed further (32 rays, down to 0.01 of the entering light) the glass comes closer
// to the path tracer (1024 samples per pixel) over the pixels wholly on the relic. This is the
// cause of the Khronos hurricane glass's missing blue under the park (docs/materials.md); the
// defaults stay where they are because the glass vase's foreground bar needs the sum
// (docs/tracer/glass.md), so this holds the cause for the thin-wall rule still to come.
TEST(Refraction, LightGuidedInsideAThinCurvedWallIsLostByTheParallelWallsSum) {
  Material glass = clearGlass(1.5f, 0.002f);
  glass.attenuation_colour = vec3(0.7f, 0.85f, 1.0f);
  glass.attenuation_distance = 0.005f;
  constexpr float kRadius = 0.1f, kWall = 0.002f;
  Model tumbler;
  tumbler.meshes.push_back(makeLathe({{kRadius - kWall, 0.2f},
                                      {kRadius, 0.2f},
                                      {kRadius, 0.4f},
                                      {kRadius - kWall, 0.4f},
                                      {kRadius - kWall, 0.2f}},
                                     96));
  tumbler.materials.push_back(glass);
  const RenderScene scene(tumbler, {});
  const Environment sky = panorama([](const vec3& d) {
    return d.y > 0.0f ? vec3(0.25f, 0.45f, 1.0f) * (0.4f + 0.6f * d.y) : vec3(0.12f, 0.08f, 0.04f);
  });
  const PrefilteredIbl ibl(sky, PrefilterOptions{4, 256, 8});
  constexpr int kSize = 32;
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.36f, 0.6f), vec3(0.0f, 0.3f, 0.0f), 24.0f, kSize, kSize);
  const cv::Mat truth = renderPathTraced(PathTracer(scene, sky), view, 1024);
  const auto error = [&](int branch_rays, float branch_weight) {
    TracerSettings settings = staticOnly();
    settings.refraction_branch_rays = branch_rays;
    settings.refraction_branch_weight = branch_weight;
    return relicErrorAtFourSamples(scene, ibl, view, truth, settings);
  };
  const double followed = error(32, 0.01f);
  const double summed =
      error(TracerSettings{}.refraction_branch_rays, TracerSettings{}.refraction_branch_weight);
  std::printf("thin curved wall: %.4f of the truth's mean followed, %.4f summed\n", followed, summed);
  EXPECT_LT(followed, 0.025);         // 0.0195 measured
  EXPECT_GT(summed, 1.3 * followed);  // 0.0296 measured: 1.52x
}

// A diamond under a dim sky strewn with small lamps (about 5 degrees across, up to 80 times the
// sky): at a facet's edge some of a pixel's rays leave the gem towards a lamp and the others do
// not. Where a pixel's four samples disagree by more than the contrast, each takes the mean of 16
// paths across its quarter of the pixel, so the pixel shows the lamp over its share of it. On the
// pixels that changes, the summed error against the same renderer at 4x the resolution averaged
// down (64 samples a pixel, no supersampling) falls to under half (a quarter measured: 1.15
// against 4.51), and so does the error against the path tracer's truth (1024 samples per pixel;
// 1.24 against 5.67).
TEST(Refraction, APixelWhoseSamplesDisagreeOnALampTakesPathsAcrossIt) {
  const RenderScene scene(gem(), {});
  const Environment sky = panorama([](const vec3& d) {
    float lamp = 0.0f;
    for (int i = 0; i < 48; ++i)
      lamp = std::max(lamp, std::pow(std::max(0.0f, glm::dot(d, fibonacciDirection(i, 48))), 300.0f));
    return vec3(0.05f + 0.1f * std::max(d.y, 0.0f)) + vec3(12.0f, 10.0f, 8.0f) * lamp;
  });
  const PrefilteredIbl ibl(sky, PrefilterOptions{4, 256, 8});
  constexpr int kSize = 32;
  const vec3 eye(0.3f, 0.6f, 0.7f), target(0.0f, 0.3f, 0.0f);
  const CameraModel view = lookAtCamera(eye, target, 30.0f, kSize, kSize);
  const auto render = [&](float contrast, int size, std::uint64_t* supersampled) {
    TracerSettings settings = staticOnly();
    settings.aa_samples = 4;
    settings.refraction_supersample_contrast = contrast;
    const ViewImages v = renderOnce(scene, ibl, settings, lookAtCamera(eye, target, 30.0f, size, size));
    if (supersampled) *supersampled = v.supersampled_samples;
    return v.hdr;
  };
  cv::Mat finer;
  cv::resize(render(0.0f, 4 * kSize, nullptr), finer, cv::Size(kSize, kSize), 0.0, 0.0, cv::INTER_AREA);
  std::uint64_t with_more = 0, without = 0;
  const cv::Mat more = render(TracerSettings{}.refraction_supersample_contrast, kSize, &with_more);
  const cv::Mat four = render(0.0f, kSize, &without);
  const cv::Mat truth = renderPathTraced(PathTracer(scene, sky), view, 1024);
  // Over the pixels the supersampling changed: the sum of the absolute differences of R + G + B.
  double more_vs_finer = 0.0, four_vs_finer = 0.0, more_vs_truth = 0.0, four_vs_truth = 0.0;
  int changed = 0;
  const auto sum = [](const vec3& c) { return double(c.r) + double(c.g) + double(c.b); };
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const double m = sum(rgbAt(more, x, y)), f = sum(rgbAt(four, x, y));
      if (m == f) continue;
      ++changed;
      more_vs_finer += std::abs(m - sum(rgbAt(finer, x, y)));
      four_vs_finer += std::abs(f - sum(rgbAt(finer, x, y)));
      more_vs_truth += std::abs(m - sum(rgbAt(truth, x, y)));
      four_vs_truth += std::abs(f - sum(rgbAt(truth, x, y)));
    }
  EXPECT_GT(with_more, 0u);
  EXPECT_EQ(without, 0u);
  EXPECT_GE(changed, 3);
  EXPECT_LT(more_vs_finer, 0.5 * four_vs_finer);
  EXPECT_LT(more_vs_truth, 0.5 * four_vs_truth);
}

// A hall at a finite distance (the panorama's pixels on a sphere of radius 1.2 m around a capture
// point 0.5 m above a glass sphere, PanoramaProxy): the light leaving the glass reads the hall
// where its exit ray meets it, as the path tracer sees it (256 samples per pixel), not where a ray
// from the capture point along the exit direction would. Mean absolute error over the pixels
// wholly on the sphere under 6% of the truth's mean (3.8% measured; read along the exit direction
// from the capture point instead, 44%).
TEST(Refraction, LightLeavingTheGlassSeesTheHallWithItsParallax) {
  const RenderScene scene(glassSphere(1.5f), {});
  PanoramaProxy proxy;
  proxy.centre = vec3(0.0f, 0.8f, 0.0f);
  proxy.radius = 1.2f;
  const Environment sky = panorama([](const vec3& d) {
    const float lamp = std::max(0.0f, glm::dot(d, glm::normalize(vec3(0.3f, -0.4f, 1.0f))));
    return vec3(0.05f + 0.2f * std::max(d.y, 0.0f)) + vec3(2.0f, 1.6f, 1.2f) * std::pow(lamp, 8.0f);
  });
  const Environment hall(sky.panorama(), 0.0f, proxy);
  const PrefilteredIbl ibl(hall, PrefilterOptions{4, 256, 8});
  constexpr int kSize = 32;
  const CameraModel view = lookAtCamera(vec3(0.0f, 0.4f, -0.8f), vec3(0.0f, 0.3f, 0.0f), 24.0f, kSize, kSize);
  const PathTracer tracer(scene, hall);
  const cv::Mat truth = renderPathTraced(tracer, view, 256);
  TracerSettings settings = staticOnly();
  settings.aa_samples = 4;
  const ViewImages v = renderOnce(scene, ibl, settings, view);
  int pixels = 0;
  EXPECT_LT(errorOnTheRelic(scene, view, truth, v.hdr, pixels), 0.06);
  EXPECT_GT(pixels, 200);
}

// Light reflected where a path enters a second glass wall leaves along that wall's own mirror
// direction: a bowl's back wall, seen through its front one, shows what its concave inside faces
// (the sky), not what the entry's mirror sees. A vertical slab in front, a second one behind it
// tilted 45 degrees whose face sends the view ray's reflection straight up, a sky bright above and
// black below the horizon: the second face's Fresnel share (computed here from the Fresnel
// equations) of the light through the first slab reads the zenith. Sent along the entry's mirror,
// it would read black.
TEST(Refraction, ASecondWallReflectsAlongItsOwnMirrorDirection) {
  Material glass = clearGlass(1.5f, 0.04f);
  Model model = slab(0.02f, glass);
  const float c = std::sqrt(0.5f);
  for (TriangleMesh mesh : slab(0.02f, glass).meshes) {
    for (vec3& p : mesh.positions)  // turned -45 degrees about x (front face normal (0, c, c)), 1 m behind
      p = vec3(p.x, c * p.y + c * p.z, -c * p.y + c * p.z - 1.0f);
    model.meshes.push_back(mesh);
  }
  const RenderScene scene(model, {});
  const PrefilteredIbl ibl(panorama([](const vec3& d) { return vec3(std::max(0.0f, d.y)); }),
                           PrefilterOptions{3, 256, 8});
  const TransmittedPath path = traceTransmission(scene, ibl, TracerSettings{}, 8, vec3(0.0f, 0.0f, 0.02f),
                                                 vec3(0, 0, 1), vec3(0, 0, -1), glass);
  // Fresnel, unpolarised: normal incidence r0; 45 degrees from the s and p amplitudes.
  const float n = 1.5f, r0 = (n - 1.0f) * (n - 1.0f) / ((n + 1.0f) * (n + 1.0f));
  const float cos_t = std::sqrt(1.0f - 0.5f / (n * n));
  const float rs = (c - n * cos_t) / (c + n * cos_t), rp = (n * c - cos_t) / (n * c + cos_t);
  const float f45 = 0.5f * (rs * rs + rp * rp);
  // Through the first slab: (1 - r0) in, (1 - r0) / (1 - r0^2) out (its reflections summed).
  const float through = (1.0f - r0) * (1.0f - r0) / (1.0f - r0 * r0);
  EXPECT_NEAR(path.resolved.g, through * f45, 0.05f * through * f45);
  EXPECT_EQ(path.events, 4);
}

// What a reflected ray (a metal foot's mirror ray) sees where it meets glass: the light traced
// through the glass, what stands inside it shaded as a hit point is. A white Lambert ball sealed
// in a glass slab, under an even hall of radiance 1: the point facing the slab's face has radiance
// about its albedo (the hall reaches it through the glass, whose walls reflect into its light
// about as much as out of it), seen through the slab's face with its transmission 1 - r0, plus its
// own specular share. A straight passage, as a shadow ray's, stops at the ball: black.
TEST(Refraction, ARayMeetingGlassSeesWhatStandsInsideIt) {
  Material glass = clearGlass(1.5f, 0.2f);
  Model model = slab(0.1f, glass);
  Model inner = test::sphereModel({vec3(0.8f), 0.0f, 1.0f}, 0.04f);
  inner.meshes[0].material = 1;
  model.meshes.push_back(inner.meshes[0]);
  model.materials.push_back(inner.materials[0]);
  const RenderScene scene(model, {});
  const PrefilteredIbl ibl(panorama([](const vec3&) { return vec3(1.0f); }), PrefilterOptions{3, 256, 8});
  const Ray ray{vec3(0.002f, 0.001f, 1.0f), vec3(0.0f, 0.0f, -1.0f)};  // off the slab's diagonals
  const RayHit hit = scene.relicOnly().intersect(ray);
  ASSERT_TRUE(hit.hit());
  const SurfacePoint surface = resolveSurface(scene, scene.relicOnly(), ray, hit, 0.0f);
  std::uint64_t rays = 0;
  const vec3 light = lightThroughGlass(scene, ibl, TracerSettings{}, surface, ray.direction, rays);
  const float n = 1.5f, r0 = (n - 1.0f) * (n - 1.0f) / ((n + 1.0f) * (n + 1.0f));
  const float expected = (1.0f - r0) * (0.8f + r0);  // the cube's Lambert light and its specular share
  EXPECT_NEAR(light.g, expected, 0.1f * expected);
  EXPECT_GT(rays, 2u);
  std::uint32_t straight_rays = 0;
  EXPECT_EQ(
      luminance(passedThroughRelic(scene, TracerSettings{}, surface.position, ray.direction, straight_rays)),
      0.0f);
}

}  // namespace
}  // namespace holo::reflect
