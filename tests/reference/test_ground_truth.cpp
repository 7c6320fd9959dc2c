// Independent checks of the ground-truth path tracer: every expected value here comes from a
// closed form or a deterministic quadrature written in this file, never from the renderer's own
// sampling code. G2 against the height-correlated Smith closed form; the GGX white furnace against
// a (theta, phi) quadrature of Bsdf::eval; a Lambert sphere under a quad emitter against the
// polygon form factor; a closed emitting Lambert box against the geometric series of its bounces.
#include <gtest/gtest.h>

#include <cmath>

#include "holo/reference/path_tracer.hpp"
#include "holo/reflect/bsdf.hpp"
#include "reflect_test_scenes.hpp"

namespace holo::reference {
namespace {

// The scenes, materials and environments the reference renderers read.
using namespace holo::reflect;

// Lambda(theta) = (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2 (Heitz 2014, eq. 72), in double.
double smithLambda(double theta, double alpha) {
  const double t = std::tan(theta);
  return 0.5 * (-1.0 + std::sqrt(1.0 + alpha * alpha * t * t));
}

TEST(GroundTruth, G2IsTheHeightCorrelatedSmithClosedForm) {
  const double deg = M_PI / 180.0;
  for (double alpha : {0.0001, 0.01, 0.09, 0.36, 0.64, 1.0})
    for (double to : {0.0, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0, 89.9})
      for (double ti : {0.0, 20.0, 50.0, 70.0, 80.0, 88.0, 89.5, 89.95}) {
        const double expected = 1.0 / (1.0 + smithLambda(to * deg, alpha) + smithLambda(ti * deg, alpha));
        const float g2 = ggx::G2(float(std::cos(to * deg)), float(std::cos(ti * deg)), float(alpha));
        // float cosines near grazing carry ~1e-7 absolute error, so tan^2 a relative 1e-4.
        EXPECT_NEAR(g2, expected, 2e-4 * expected + 1e-6)
            << "alpha " << alpha << " theta_o " << to << " theta_i " << ti;
      }
}

// A pixel's path samples: the mean and its standard error from the sample variance (an upper
// bound for the scrambled Sobol points the tracer draws).
struct Estimate {
  vec3 mean{0.0f};
  double std_error = 0.0;  // of the mean's green channel
  vec3 position{0.0f}, normal{0.0f};
  float n_dot_v = 0.0f;
};

Estimate trace(const PathTracer& tracer, const vec3& eye, const vec3& target, int n) {
  const Ray ray{eye, glm::normalize(target - eye)};
  const RayHit hit = tracer.scene().relicOnly().intersect(ray);
  EXPECT_TRUE(hit.hit());
  Estimate e;
  e.position = tracer.scene().relicOnly().position(ray, hit);
  e.normal = tracer.scene().relicOnly().shadingNormal(hit, ray.direction);
  e.n_dot_v = glm::dot(e.normal, -ray.direction);
  glm::dvec3 sum(0.0);
  double sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    SampleStream stream(23, 0, std::uint32_t(i));
    const vec3 L = tracer.traceFromRelic(ray, hit, stream);
    EXPECT_TRUE(isFinite(L));
    sum += glm::dvec3(L);
    sum2 += double(L.y) * double(L.y);
  }
  e.mean = vec3(sum / double(n));
  const double var = std::max(0.0, sum2 / n - double(e.mean.y) * double(e.mean.y));
  e.std_error = std::sqrt(var / (n - 1));
  return e;
}

// Directional albedo of `m` seen from cos(theta_o) = mu: the integral of Bsdf::eval (f cos) over
// the hemisphere by the midpoint rule on a (theta, phi) grid; the lobe is symmetric in phi, so
// half the azimuths are integrated and doubled.
double albedoByQuadrature(const SurfaceMaterial& m, float mu, int n_theta, int n_phi) {
  const Bsdf bsdf(m, vec3(0, 0, 1));
  const vec3 wo(std::sqrt(std::max(0.0f, 1.0f - mu * mu)), 0.0f, mu);
  const double d_theta = 0.5 * M_PI / n_theta, d_phi = M_PI / n_phi;
  double sum = 0.0;
  for (int i = 0; i < n_theta; ++i) {
    const double theta = (i + 0.5) * d_theta;
    double ring = 0.0;
    for (int j = 0; j < n_phi; ++j) {
      const double phi = (j + 0.5) * d_phi;
      const vec3 wi(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                    float(std::cos(theta)));
      ring += bsdf.eval(wo, wi).x;
    }
    sum += ring * std::sin(theta) * d_theta * d_phi;
  }
  return 2.0 * sum;
}

TEST(GroundTruth, GgxWhiteFurnaceMatchesTheQuadratureOfEval) {
  // F0 = 1 metal sphere under a white sky: it scatters once (convex), so a pixel's radiance is
  // the directional albedo at its n.v, which the quadrature of eval() gives without the sampler.
  const Environment env = Environment::uniform(vec3(1.0f));
  const std::vector<std::pair<vec3, vec3>> views = {
      {vec3(0, 0, 4), vec3(0, 0, 1)},
      {vec3(0, 0, 4), vec3(0.7071f, 0, 0.7071f)},
      {vec3(0, 0, 4), vec3(0.9397f, 0.0f, 0.3420f)},  // n.v ~ 0.1
  };
  for (float roughness : {0.0f, 0.3f, 0.6f, 1.0f}) {
    const SurfaceMaterial metal{vec3(1.0f), 1.0f, roughness, 1.0f};
    // A mirror (a delta lobe, which eval() never sees) reflects exactly everything.
    const bool mirror = roughness < kDeltaRoughness;
    // Finely tessellated so that rough-lobe rays at grazing views do not re-enter the facets.
    const RenderScene scene(test::sphereModel(metal, 1.0f, vec3(0.0f), 192, 384), {});
    const PathTracer tracer(scene, env);
    for (const auto& [eye, target] : views) {
      const Estimate e = trace(tracer, eye, target, 1024);
      const double expected = mirror ? 1.0 : albedoByQuadrature(metal, e.n_dot_v, 512, 2048);
      EXPECT_NEAR(e.mean.x, expected, 0.005 * expected) << "roughness " << roughness << " n.v " << e.n_dot_v;
      EXPECT_LE(expected, 1.0 + 1e-3);
    }
  }
}

// Irradiance at `p` (unit normal `n`) from a uniform polygon emitter of radiance L wholly above
// p's horizon: E = L/2 sum_i gamma_i n . (R_i x R_i+1) / |R_i x R_i+1|, gamma_i the angle between
// the unit directions R_i, R_i+1 to consecutive vertices (Lambert's polygon formula).
double polygonIrradiance(const vec3& p, const vec3& n, const std::vector<vec3>& vertices, double radiance) {
  double sum = 0.0;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const glm::dvec3 a = glm::normalize(glm::dvec3(vertices[i] - p));
    const glm::dvec3 b = glm::normalize(glm::dvec3(vertices[(i + 1) % vertices.size()] - p));
    const double gamma = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    sum += gamma * glm::dot(glm::dvec3(n), glm::normalize(glm::cross(a, b)));
  }
  return 0.5 * radiance * std::abs(sum);
}

TEST(GroundTruth, LambertSphereUnderAQuadEmitterMatchesTheFormFactor) {
  // A grey Lambert sphere (specular 0) in a black sky under a 2 m square emitter 1 m above its
  // top; each lit point sees the whole emitter above its horizon, so its radiance is
  // albedo / pi * E with E from the polygon formula.
  const float albedo = 0.6f, emitted = 3.0f;
  const SurfaceMaterial lambert{vec3(albedo), 0.0f, 1.0f, 0.0f};
  const Model emitter = test::emitterQuad(vec3(0, 2, 0), vec3(0, -1, 0), 2.0f, vec3(emitted));
  RenderScene scene(test::sphereModel(lambert), {emitter});
  scene.overrideRelicMaterial(lambert);
  const Environment black = Environment::uniform(vec3(0.0f));
  const PathTracer tracer(scene, black);
  for (const vec3& dir : {glm::normalize(vec3(0.5f, 0.866f, 0.0f)), glm::normalize(vec3(0.0f, 0.94f, 0.342f)),
                          glm::normalize(vec3(-0.2f, 0.97f, -0.1f))}) {
    const Estimate e = trace(tracer, 3.5f * dir, dir, 8192);
    const double expected =
        albedo / M_PI * polygonIrradiance(e.position, e.normal, emitter.meshes[0].positions, emitted);
    EXPECT_GT(e.std_error, 0.0);
    EXPECT_NEAR(e.mean.y, expected, 4.0 * e.std_error + 1e-3 * expected)
        << "normal " << dir.x << "," << dir.z;
  }
}

// A closed cube of side 2 (the relic) around the origin, its faces wound outwards.
Model closedBox(const Material& material) {
  TriangleMesh mesh;
  mesh.name = "box";
  for (int i = 0; i < 8; ++i) mesh.positions.push_back(vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  Model model;
  model.meshes.push_back(mesh);
  model.materials.push_back(material);
  return model;
}

TEST(GroundTruth, ClosedEmittingLambertBoxSumsItsBounces) {
  // Every wall Lambert of albedo a and emitting Le, the eye inside: a path sees Le at the camera
  // ray's hit and after each of its at most N scatterings with throughput a^k, so the pixel is
  // exactly Le (1 - a^(N+1)) / (1 - a) (every sample alike: cosine sampling's weight is a), and
  // the cap's bias against the infinite-bounce Le / (1 - a) is a^(N+1) of it.
  const float emitted = 2.0f;
  for (float a : {0.5f, 0.8f}) {
    Material glow;
    glow.emission = vec3(emitted);
    glow.double_sided = true;  // seen from inside: a single-sided material's back faces are culled
    RenderScene scene(closedBox(glow), {});
    scene.overrideRelicMaterial({vec3(a), 0.0f, 1.0f, 0.0f});
    const Environment sky = Environment::uniform(vec3(0.0f));
    for (int cap : {1, 2, 5, 64}) {
      PathTracerOptions options;
      options.max_bounces = cap;
      const PathTracer tracer(scene, sky, options);
      const Estimate e = trace(tracer, vec3(0.1f, 0.2f, 0.3f), vec3(0.3f, -0.2f, -1.0f), 256);
      const double infinite = emitted / (1.0 - a);
      const double capped = infinite * (1.0 - std::pow(double(a), cap + 1));
      EXPECT_NEAR(e.mean.y, capped, 1e-4 * capped) << "a " << a << " cap " << cap;
      EXPECT_NEAR(1.0 - e.mean.y / infinite, std::pow(double(a), cap + 1), 1e-4)
          << "a " << a << " cap " << cap;
    }
  }
}

}  // namespace
}  // namespace holo::reference
