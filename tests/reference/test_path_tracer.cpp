// The ground-truth path tracer against analytic answers: the Lambert white furnace, the exact
// mirror, a Lambert sphere under a linear environment, the three light-sampling strategies agreeing,
// variance falling at least as 1/spp, determinism, and hostile inputs staying finite.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include "holo/core/equirect.hpp"
#include "holo/core/image.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reflect/view.hpp"
#include "reflect_test_scenes.hpp"

namespace holo::reference {
namespace {

// The scenes, materials and environments the reference renderers read.
using namespace holo::reflect;

using test::sphereModel;

// Mean of `n` path samples along the ray from `eye` towards the sphere point with unit normal
// `towards` (the sphere is the unit sphere at the origin). Also returns the hit's n.v.
struct PixelEstimate {
  double mean[3] = {0, 0, 0};
  double max_luminance = 0;
  float n_dot_v = 0;
  vec3 normal{0.0f};
};

PixelEstimate estimate(const PathTracer& tracer, const vec3& eye, const vec3& target, int n,
                       std::uint32_t pixel = 0) {
  const Ray ray{eye, glm::normalize(target - eye)};
  const RayHit hit = tracer.scene().relicOnly().intersect(ray);
  EXPECT_TRUE(hit.hit());
  PixelEstimate e;
  e.normal = tracer.scene().relicOnly().shadingNormal(hit, ray.direction);
  e.n_dot_v = glm::dot(e.normal, -ray.direction);
  for (int i = 0; i < n; ++i) {
    SampleStream s(17, pixel, std::uint32_t(i));
    const vec3 L = tracer.traceFromRelic(ray, hit, s);
    EXPECT_TRUE(isFinite(L));
    for (int c = 0; c < 3; ++c) e.mean[c] += L[c] / n;
    e.max_luminance = std::max(e.max_luminance, double(luminance(L)));
  }
  return e;
}

// Eyes that see the unit sphere head-on, at 45 degrees and near grazing. (Closer to grazing, the
// tessellated sphere's interpolated normals send mirror rays into its own facets; the hard-case
// test below covers exact grazing for finiteness.)
const std::vector<std::pair<vec3, vec3>> kViews = {
    {vec3(0, 0, 4), vec3(0, 0, 1)},
    {vec3(0, 0, 4), vec3(0.7071f, 0, 0.7071f)},
    {vec3(0, 0, 4), vec3(0.9397f, 0.0f, 0.3420f)},  // n.v ~ 0.1
};

TEST(PathTracer, WhiteFurnaceLambertReflectsExactlyOne) {
  // specular 0 turns the dielectric Fresnel off: a pure white Lambert surface, albedo 1.
  RenderScene scene(sphereModel({vec3(1.0f), 0.0f, 1.0f, 0.0f}), {});
  scene.overrideRelicMaterial({vec3(1.0f), 0.0f, 1.0f, 0.0f});
  const Environment env = Environment::uniform(vec3(1.0f));
  const PathTracer tracer(scene, env);
  for (const auto& [eye, target] : kViews) {
    const PixelEstimate e = estimate(tracer, eye, target, 1024);
    EXPECT_NEAR(e.mean[1], 1.0, 0.005) << "target " << target.x;
    EXPECT_LE(e.mean[1], 1.0 + 0.005);
  }
}

// A panorama that is red towards -X (the viewer's left when looking down -Z), blue towards +X,
// with a smooth vertical gradient: asymmetric in every axis.
cv::Mat asymmetricPanorama(int w = 256, int h = 128) {
  cv::Mat pano(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const vec3 d = equirect::uvToDirection({(x + 0.5f) / w, (y + 0.5f) / h});
      const vec3 rgb(d.x < 0 ? 1.0f : 0.05f, 0.2f + 0.1f * d.y, d.x > 0 ? 1.0f : 0.05f);
      setRgb(pano, x, y, rgb);
    }
  return pano;
}

TEST(PathTracer, MirrorReflectsTheEnvironmentAlongTheReflectedDirection) {
  const RenderScene scene(sphereModel({vec3(1.0f), 1.0f, 0.0f, 1.0f}), {});
  const Environment env(asymmetricPanorama());
  const PathTracer tracer(scene, env);
  for (const auto& [eye, target] : kViews) {
    const Ray ray{eye, glm::normalize(target - eye)};
    const RayHit hit = scene.relicOnly().intersect(ray);
    const vec3 n = scene.relicOnly().shadingNormal(hit, ray.direction);
    const vec3 expected = env.radiance(glm::reflect(ray.direction, n));
    for (int i = 0; i < 8; ++i) {
      SampleStream s(3, 0, std::uint32_t(i));
      const vec3 L = tracer.traceFromRelic(ray, hit, s);
      EXPECT_NEAR(glm::length(L - expected), 0.0f, 1e-5f);  // exact: no noise at all
    }
  }
}

TEST(PathTracer, MirrorShowsLeftOnTheLeft) {
  // The documented panorama convention (core/equirect.hpp): a viewer in front of a mirror ball
  // sees what is on their left in the room on the left half of the ball, as a real mirror shows.
  const RenderScene scene(sphereModel({vec3(1.0f), 1.0f, 0.0f, 1.0f}), {});
  const Environment env(asymmetricPanorama());
  const PathTracer tracer(scene, env);
  const CameraModel camera = lookAtCamera(vec3(0, 0, 5), vec3(0.0f), 30.0f, 32, 32);
  const cv::Mat image = renderPathTraced(tracer, camera, 1);
  double left_red = 0, right_red = 0, left_blue = 0, right_blue = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const vec3 c = rgbAt(image, x, y);
      (x < image.cols / 2 ? left_red : right_red) += c.r;
      (x < image.cols / 2 ? left_blue : right_blue) += c.b;
    }
  EXPECT_GT(left_red, 5.0 * right_red);
  EXPECT_GT(right_blue, 5.0 * left_blue);
}

TEST(PathTracer, LambertUnderLinearEnvironmentMatchesIrradiance) {
  // L(w) = 1 + 0.5 w.y gives E(n) = pi + 0.5 (2 pi / 3) n.y (Ramamoorthi & Hanrahan's band-1
  // kernel 2 pi / 3), so a white Lambert surface shows E / pi = 1 + n.y / 3.
  cv::Mat pano(256, 512, CV_32FC3);
  for (int y = 0; y < pano.rows; ++y)
    for (int x = 0; x < pano.cols; ++x) {
      const vec3 d = equirect::uvToDirection({(x + 0.5f) / pano.cols, (y + 0.5f) / pano.rows});
      setRgb(pano, x, y, vec3(1.0f + 0.5f * d.y));
    }
  const Environment env(pano);
  RenderScene scene(sphereModel({vec3(1.0f), 0.0f, 1.0f, 0.0f}), {});
  scene.overrideRelicMaterial({vec3(1.0f), 0.0f, 1.0f, 0.0f});
  const PathTracer tracer(scene, env);
  for (const vec3& target : {vec3(0, 1, 0.2f), vec3(0.6f, 0.3f, 0.74f), vec3(0, -0.8f, 0.6f)}) {
    const vec3 t = glm::normalize(target);
    const PixelEstimate e = estimate(tracer, 4.0f * t + vec3(0, 0, 0.5f), t, 2048);
    const double expected = 1.0 + e.normal.y / 3.0;
    EXPECT_NEAR(e.mean[1], expected, 0.005 * expected) << "normal.y " << e.normal.y;
  }
}

double meanLuminance(const cv::Mat& image) {
  const cv::Scalar m = cv::mean(image);
  return 0.0722 * m[0] + 0.7152 * m[1] + 0.2126 * m[2];
}

// A rough, partly diffuse sphere under a bright "sun" (0.2 sr, 20x the sky) and a dim sky:
// noisy for BSDF sampling alone, easy for environment sampling.
cv::Mat sunPanorama() {
  cv::Mat pano(64, 128, CV_32FC3, cv::Scalar(0.3, 0.2, 0.1));
  for (int y = 10; y < 22; ++y)
    for (int x = 56; x < 72; ++x) pano.at<cv::Vec3f>(y, x) = cv::Vec3f(5, 5, 5);
  return pano;
}

TEST(PathTracer, MisBsdfOnlyAndEnvironmentOnlyAgree) {
  const RenderScene scene(sphereModel({vec3(0.8f, 0.6f, 0.4f), 0.3f, 0.6f, 1.0f}), {});
  const Environment env(sunPanorama());
  const CameraModel camera = lookAtCamera(vec3(0, 0.5f, 4), vec3(0.0f), 35.0f, 16, 16);
  std::vector<double> means;
  for (LightSampling mode :
       {LightSampling::kMis, LightSampling::kBsdfOnly, LightSampling::kEnvironmentOnly}) {
    PathTracerOptions options;
    options.sampling = mode;
    const PathTracer tracer(scene, env, options);
    means.push_back(meanLuminance(renderPathTraced(tracer, camera, 1024)));
  }
  // 262k path samples per strategy; 1.5% is about 3 standard errors of the BSDF-only mean.
  EXPECT_GT(means[0], 0.05);
  EXPECT_NEAR(means[1], means[0], 0.015 * means[0]);
  EXPECT_NEAR(means[2], means[0], 0.015 * means[0]);
}

// Per-pixel variance of a k-spp render, from the difference of two independently seeded renders.
double varianceAt(const PathTracer& base, const CameraModel& camera, int spp) {
  PathTracerOptions a = base.options(), b = base.options();
  a.seed = 101;
  b.seed = 202;
  const PathTracer ta(base.scene(), base.environment(), a), tb(base.scene(), base.environment(), b);
  cv::Mat diff = renderPathTraced(ta, camera, spp) - renderPathTraced(tb, camera, spp);
  return 0.5 * cv::mean(diff.mul(diff))[1];
}

TEST(PathTracer, VarianceFallsAtLeastAsOneOverSpp) {
  const RenderScene scene(sphereModel({vec3(0.8f, 0.6f, 0.4f), 0.3f, 0.6f, 1.0f}), {});
  const Environment env(sunPanorama());
  const PathTracer tracer(scene, env);
  const CameraModel camera = lookAtCamera(vec3(0, 0.5f, 4), vec3(0.0f), 35.0f, 24, 24);
  const double v4 = varianceAt(tracer, camera, 4), v64 = varianceAt(tracer, camera, 64);
  ASSERT_GT(v4, 0.0);
  // 16x the samples: at least 16x less variance (low-discrepancy samples may do better), with
  // 30% slack for the variance estimate itself.
  EXPECT_LT(v64, 1.3 * v4 / 16.0) << "v4 " << v4 << " v64 " << v64;
}

TEST(PathTracer, SameSeedSameImageWhateverTheThreads) {
  const RenderScene scene(sphereModel({vec3(0.8f, 0.6f, 0.4f), 0.3f, 0.6f, 1.0f}), {});
  const Environment env(sunPanorama());
  const PathTracer tracer(scene, env);
  const CameraModel camera = lookAtCamera(vec3(0, 0.5f, 4), vec3(0.0f), 35.0f, 20, 20);
  const cv::Mat a = renderPathTraced(tracer, camera, 8);
  cv::Mat b;
  {
    const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    b = renderPathTraced(tracer, camera, 8);
  }
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  // Progressive passes continue the same sequences: 2 x 4 spp equals 8 spp.
  ProgressiveRender progressive(tracer, camera);
  progressive.addSamples(4);
  progressive.addSamples(4);
  EXPECT_EQ(progressive.samplesPerPixel(), 8);
  EXPECT_LT(cv::norm(a, progressive.image(), cv::NORM_INF), 1e-5);
  // Another seed gives another image.
  PathTracerOptions other;
  other.seed = 2;
  const PathTracer tracer2(scene, env, other);
  EXPECT_GT(cv::norm(a, renderPathTraced(tracer2, camera, 8), cv::NORM_INF), 0.0);
}

void expectFiniteImage(const cv::Mat& image) {
  ASSERT_FALSE(image.empty());
  EXPECT_TRUE(cv::checkRange(image));
  double lo = 0;
  cv::minMaxLoc(image.reshape(1), &lo);
  EXPECT_GE(lo, 0.0);
}

TEST(PathTracer, HostilePanoramasStayFinite) {
  const RenderScene scene(sphereModel({vec3(0.9f), 0.5f, 0.4f, 1.0f}), {});
  const CameraModel camera = lookAtCamera(vec3(0, 0, 4), vec3(0.0f), 35.0f, 16, 16);
  cv::Mat broken(32, 64, CV_32FC3, cv::Scalar::all(0.5));
  broken.at<cv::Vec3f>(3, 5) = cv::Vec3f(NAN, INFINITY, -INFINITY);
  broken.at<cv::Vec3f>(20, 40) = cv::Vec3f(-5, -5, -5);
  cv::Mat single(32, 64, CV_32FC3, cv::Scalar::all(0));
  single.at<cv::Vec3f>(12, 30) = cv::Vec3f(1e6f, 1e6f, 1e6f);
  for (const cv::Mat& pano : {broken, single}) {
    const Environment env(pano);
    const PathTracer tracer(scene, env);
    PathTracerStats stats;
    const cv::Mat image = renderPathTraced(tracer, camera, 16, &stats);
    expectFiniteImage(image);
    EXPECT_EQ(stats.nonfinite_dropped, 0);
    EXPECT_GT(cv::norm(image), 0.0);
  }
  const Environment black = Environment::uniform(vec3(0.0f));
  const PathTracer tracer(scene, black);
  EXPECT_EQ(cv::norm(renderPathTraced(tracer, camera, 8)), 0.0);
}

TEST(PathTracer, FireflyClampReportsTheEnergyItRemoves) {
  const RenderScene scene(sphereModel({vec3(0.9f), 0.0f, 0.5f, 1.0f}), {});
  cv::Mat single(32, 64, CV_32FC3, cv::Scalar::all(0.1));
  single.at<cv::Vec3f>(12, 30) = cv::Vec3f(1e6f, 1e6f, 1e6f);
  const Environment env(single);
  const CameraModel camera = lookAtCamera(vec3(0, 0, 4), vec3(0.0f), 35.0f, 16, 16);
  PathTracerOptions options;
  options.firefly_clamp = 1.0f;
  PathTracerStats clamped, plain;
  const PathTracer with_clamp(scene, env, options), without(scene, env);
  const double kept = meanLuminance(renderPathTraced(with_clamp, camera, 8, &clamped));
  const double all = meanLuminance(renderPathTraced(without, camera, 8, &plain));
  EXPECT_GT(clamped.clamped, 0);
  EXPECT_GT(clamped.clampedFraction(), 0.5);  // the 1e6 pixel carries most of the energy
  EXPECT_EQ(plain.clamped, 0);
  EXPECT_EQ(plain.clampedFraction(), 0.0);
  // What the clamp reports as removed is what is missing from the image (same samples).
  const double pixels = double(camera.width()) * camera.height() * 8;
  EXPECT_NEAR((all - kept) * pixels, clamped.clamped_energy, 1e-3 * clamped.clamped_energy);
}

TEST(PathTracer, DegenerateGeometryAndInwardNormalsStayFinite) {
  Model relic = sphereModel({vec3(0.9f), 1.0f, 0.2f, 1.0f}, 1.0f, vec3(0.0f), 12, 24);
  TriangleMesh& mesh = relic.meshes[0];
  for (vec3& n : mesh.normals) n = -n;  // normals facing away from every viewer
  const unsigned base = unsigned(mesh.positions.size());
  mesh.positions.push_back(vec3(0, 0, 1.5f));
  mesh.positions.push_back(vec3(0, 0, 1.5f));  // coincident vertices
  mesh.positions.push_back(vec3(1, 1, 1.5f));
  mesh.positions.push_back(vec3(2, 2, 1.5f));                      // collinear: zero area
  for (int i = 0; i < 4; ++i) mesh.normals.push_back(vec3(0.0f));  // zero-length normals
  mesh.triangles.push_back({base, base + 1, base + 2});
  mesh.triangles.push_back({base, base + 2, base + 3});
  const RenderScene scene(relic, {test::emitterQuad(vec3(0, 3, 0), vec3(0, -1, 0), 1.0f, vec3(5.0f))});
  const Environment env(asymmetricPanorama(64, 32));
  const PathTracer tracer(scene, env);
  // An axis-parallel view and a grazing one.
  for (const vec3& eye : {vec3(0, 0, 4), vec3(4, 0.999f, 0)}) {
    PathTracerStats stats;
    expectFiniteImage(renderPathTraced(tracer, lookAtCamera(eye, vec3(0.0f), 40.0f, 16, 16), 8, &stats));
    EXPECT_EQ(stats.nonfinite_dropped, 0);
  }
}

TEST(PathTracer, EmittersLightTheRelicAndShadowTheEnvironment) {
  // A white Lambert sphere in a black sky with an emitter above it: the top is lit, the bottom
  // is not; with a bright sky and an opaque black emitter overhead, the top gets darker.
  RenderScene scene(sphereModel({vec3(1.0f), 0.0f, 1.0f, 0.0f}),
                    {test::emitterQuad(vec3(0, 2, 0), vec3(0, -1, 0), 2.0f, vec3(1.0f))});
  scene.overrideRelicMaterial({vec3(1.0f), 0.0f, 1.0f, 0.0f});
  const Environment black = Environment::uniform(vec3(0.0f));
  const PathTracer lit(scene, black);
  const double top = estimate(lit, vec3(0, 4, 0.5f), vec3(0, 1, 0.1f), 512).mean[1];
  const double bottom = estimate(lit, vec3(0, -4, 0.5f), vec3(0, -1, 0.1f), 512).mean[1];
  EXPECT_GT(top, 0.1);
  EXPECT_EQ(bottom, 0.0);
  const RenderScene shadowing(sphereModel({vec3(1.0f), 0.0f, 1.0f, 0.0f}),
                              {test::emitterQuad(vec3(0, 2, 0), vec3(0, -1, 0), 2.0f, vec3(0.0f))});
  const Environment sky = Environment::uniform(vec3(1.0f));
  const PathTracer shadowed(shadowing, sky);
  EXPECT_LT(estimate(shadowed, vec3(0, 4, 0.5f), vec3(0, 1, 0.1f), 512).mean[1], 0.9);
}

}  // namespace
}  // namespace holo::reference
