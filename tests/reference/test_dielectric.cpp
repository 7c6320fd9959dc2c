// The ground truth's glass (dielectric.hpp, path_tracer.hpp) against answers computed here from
// optics, not from the implementation: Snell's law and the critical angle, the slab's
// transmittance (1-R)^2 a / (1 - R^2 a^2), an invisible glass sphere in a white furnace, IOR 1
// showing what is behind; the rough BTDF's generalised reciprocity and energy bound by Monte
// Carlo; hostile materials staying finite; the built-in glass relics as closed volumes.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/image.hpp"
#include "holo/reference/dielectric.hpp"
#include "holo/reference/path_tracer.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"
#include "reflect_test_scenes.hpp"
#include "shared_data.hpp"

namespace holo::reference {
namespace {

// The scenes, materials and environments the reference renderers read.
using namespace holo::reflect;

SurfaceMaterial glass(float ior, float roughness = 0.0f) {
  SurfaceMaterial m;
  m.base_colour = vec3(1.0f);
  m.metallic = 0.0f;
  m.roughness = roughness;
  m.transmission = 1.0f;
  m.ior = ior;
  m.thin_walled = false;
  return m;
}

// A closed box, wound counter-clockwise seen from outside (each face its own four vertices).
Model boxModel(const vec3& lo, const vec3& hi) {
  TriangleMesh mesh;
  mesh.name = "box";
  const vec3 c = 0.5f * (lo + hi);
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      vec3 n(0.0f);
      n[axis] = side ? 1.0f : -1.0f;
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      const auto base = static_cast<unsigned>(mesh.positions.size());
      for (int k = 0; k < 4; ++k) {
        vec3 p;
        p[axis] = side ? hi[axis] : lo[axis];
        p[a] = (k == 1 || k == 2) ? hi[a] : lo[a];
        p[b] = (k >= 2) ? hi[b] : lo[b];
        mesh.positions.push_back(p);
        mesh.normals.push_back(n);
      }
      uvec3 t0{base, base + 1, base + 2}, t1{base, base + 2, base + 3};
      const vec3 w = glm::cross(mesh.positions[base + 1] - mesh.positions[base],
                                mesh.positions[base + 2] - mesh.positions[base]);
      if (glm::dot(w, mesh.positions[base] - c) < 0.0f) std::swap(t0.y, t0.z), std::swap(t1.y, t1.z);
      mesh.triangles.push_back(t0);
      mesh.triangles.push_back(t1);
    }
  Model model;
  model.meshes.push_back(mesh);
  model.materials.emplace_back();
  return model;
}

// Mean of n path samples along one ray (fixed seed).
vec3 meanAlong(const PathTracer& tracer, const Ray& ray, int n, std::int64_t* truncated = nullptr,
               double* truncated_throughput = nullptr) {
  const RayHit hit = tracer.scene().relicOnly().intersect(ray);
  EXPECT_TRUE(hit.hit());
  if (!hit.hit()) return vec3(0.0f);
  glm::dvec3 sum(0.0);
  for (int i = 0; i < n; ++i) {
    SampleStream s(5, 0, std::uint32_t(i));
    PathRecord record;
    const vec3 L = tracer.traceFromRelic(ray, hit, s, 0.0f, &record);
    EXPECT_TRUE(isFinite(L));
    sum += glm::dvec3(L);
    if (truncated && record.truncated) ++*truncated;
    if (truncated_throughput) *truncated_throughput += record.truncated_throughput;
  }
  return vec3(sum / double(n));
}

// Radiance 1 within `half_angle` of `direction`, 0 elsewhere: what a ray leaving along
// `direction` sees, and nothing else.
Environment spot(const vec3& direction, float half_angle) {
  cv::Mat pano(128, 256, CV_32FC3, cv::Scalar::all(0));
  for (int y = 0; y < pano.rows; ++y)
    for (int x = 0; x < pano.cols; ++x) {
      const vec3 d = equirect::uvToDirection({(x + 0.5f) / pano.cols, (y + 0.5f) / pano.rows});
      if (glm::dot(d, direction) > std::cos(half_angle)) setRgb(pano, x, y, vec3(1.0f));
    }
  return Environment(pano);
}

TEST(Dielectric, RefractionFollowsSnell) {
  const vec3 n(0, 0, 1);
  for (const float eta : {1.5f, 2.42f, 1.0f / 1.5f, 1.33f})
    for (const float deg : {0.0f, 10.0f, 30.0f, 40.0f, 60.0f, 85.0f}) {
      const float theta_i = glm::radians(deg);
      const float sin_t = std::sin(theta_i) / eta;
      if (sin_t >= 1.0f) continue;  // beyond the critical angle: the next test
      const vec3 wo(std::sin(theta_i), 0.0f, std::cos(theta_i));
      // u.x just below 1 picks transmission whenever anything is transmitted.
      const DielectricBsdf bsdf(glass(1.5f), n, eta, vec3(1.0f), false);
      const auto s = bsdf.sample(wo, vec3(0.9999f, 0.5f, 0.5f));
      ASSERT_TRUE(s) << eta << " " << deg;
      EXPECT_TRUE(s->transmitted && s->delta);
      EXPECT_LT(s->wi.z, 0.0f);
      EXPECT_NEAR(std::sqrt(s->wi.x * s->wi.x + s->wi.y * s->wi.y), sin_t, 1e-5f) << eta << " " << deg;
      EXPECT_LE(s->wi.x, 0.0f);  // the other side of the normal from wo
      // Smooth refraction carries radiance times (1 - R) / eta^2, chosen with probability 1 - R.
      EXPECT_NEAR(s->weight.x, 1.0f / (eta * eta), 1e-4f);
    }
}

TEST(Dielectric, BeyondTheCriticalAngleReflectsTotally) {
  const float eta = 1.0f / 1.5f;  // glass to air
  const float critical = std::asin(eta);
  for (const float theta : {critical + 0.01f, 0.5f * (critical + 0.5f * kPi), glm::radians(89.0f)}) {
    const vec3 wo(std::sin(theta), 0.0f, std::cos(theta));
    EXPECT_EQ(fresnelDielectric(wo.z, eta), 1.0f);
    for (const float roughness : {0.0f, 0.02f}) {
      const DielectricBsdf bsdf(glass(1.5f, roughness), vec3(0, 0, 1), eta, vec3(1.0f), false);
      for (const float u : {0.0f, 0.5f, 0.9999f}) {
        const auto s = bsdf.sample(wo, vec3(u, 0.5f, 0.5f));
        if (!s) continue;  // a rough sample may fall below the surface: lost, never transmitted
        EXPECT_FALSE(s->transmitted);
        EXPECT_GT(s->wi.z, 0.0f);
        if (roughness == 0.0f) {
          EXPECT_NEAR(s->wi.x, -wo.x, 1e-5f);
          EXPECT_NEAR(s->weight.y, 1.0f, 1e-6f);  // everything reflected
        }
      }
    }
  }
  // Just inside the critical angle something is transmitted.
  EXPECT_LT(fresnelDielectric(std::cos(critical - 0.01f), eta), 1.0f);
  // Normal incidence: ((n - 1) / (n + 1))^2.
  EXPECT_NEAR(fresnelDielectric(1.0f, 1.5f), 0.04f, 1e-6f);
  EXPECT_NEAR(fresnelDielectric(1.0f, 1.0f / 1.5f), 0.04f, 1e-6f);
}

// Slab of thickness d at normal incidence, absorbing with sigma: T = (1-R)^2 a / (1 - R^2 a^2).
TEST(Dielectric, SlabAtNormalIncidenceTransmitsTheSeriesSum) {
  const float d = 0.02f;
  const Environment env = spot(vec3(0, 0, -1), 0.15f);
  for (const float ior : {1.5f, 2.42f})
    for (const float colour : {1.0f, 0.5f}) {
      SurfaceMaterial m = glass(ior);
      m.attenuation_colour = vec3(colour);
      m.attenuation_distance = 0.01f;
      RenderScene scene(boxModel({-1, -1, -0.5f * d}, {1, 1, 0.5f * d}), {});
      scene.overrideRelicMaterial(m);
      PathTracerOptions options;
      options.sampling = LightSampling::kBsdfOnly;
      const PathTracer tracer(scene, env, options);
      const vec3 L = meanAlong(tracer, {{0.1f, 0.2f, 1.0f}, {0, 0, -1}}, 32768);
      const double R = std::pow((ior - 1.0) / (ior + 1.0), 2.0);
      const double sigma = -std::log(double(colour)) / 0.01;
      const double a = std::exp(-sigma * d);
      const double expected = (1 - R) * (1 - R) * a / (1 - R * R * a * a);
      EXPECT_NEAR(L.y, expected, 0.01 * expected) << "ior " << ior << " colour " << colour;
    }
}

// An emitter (a visitor, in the museum) seen through the slab: Le times the same series, the
// environment black. The camera ray sees the relic only; the emitter is reached through it.
TEST(Dielectric, EmitterBehindTheSlabIsSeenThroughIt) {
  const float d = 0.05f, ior = 1.5f;
  SurfaceMaterial m = glass(ior);
  m.attenuation_colour = vec3(0.6f, 0.8f, 1.0f);
  m.attenuation_distance = 0.1f;
  const vec3 le(2.0f, 1.0f, 0.5f);
  RenderScene scene(boxModel({-1, -1, -0.5f * d}, {1, 1, 0.5f * d}),
                    {test::emitterQuad({0, 0, -1}, {0, 0, 1}, 4.0f, le)});
  scene.overrideRelicMaterial(m);
  const Environment env = Environment::uniform(vec3(0.0f));
  PathTracerOptions options;
  options.sampling = LightSampling::kBsdfOnly;
  const PathTracer tracer(scene, env, options);
  const vec3 L = meanAlong(tracer, {{0.05f, -0.1f, 1.0f}, {0, 0, -1}}, 32768);
  const double R = std::pow((ior - 1.0) / (ior + 1.0), 2.0);
  for (int c = 0; c < 3; ++c) {
    const double a = std::pow(double(m.attenuation_colour[c]), d / 0.1);  // exp(-sigma d)
    const double expected = le[c] * (1 - R) * (1 - R) * a / (1 - R * R * a * a);
    EXPECT_NEAR(L[c], expected, 0.01 * expected) << c;
  }
}

// A non-absorbing glass sphere in a uniform white environment is invisible: every path leaves
// with weight 1 (refraction's 1/eta^2 and eta^2 cancel), so every covered pixel is 1.
cv::Mat furnace(const SurfaceMaterial& m, int spp, cv::Mat* covered, PathTracerStats* stats = nullptr,
                int size = 24) {
  RenderScene scene(test::sphereModel(m, 1.0f, vec3(0.0f), 96, 192), {});
  scene.overrideRelicMaterial(m);
  const Environment env = Environment::uniform(vec3(1.0f));
  const PathTracer tracer(scene, env);
  const CameraModel camera = lookAtCamera({0, 0, 3.5f}, {0, 0, 0}, 40.0f, size, size);
  // A pixel counts when its four corners see the sphere (no partial coverage).
  *covered = cv::Mat(size, size, CV_8U, cv::Scalar(0));
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      bool all = true;
      for (const vec2 corner : {vec2(-0.5f, -0.5f), vec2(0.5f, -0.5f), vec2(-0.5f, 0.5f), vec2(0.5f, 0.5f)})
        all = all && scene.relicOnly().intersect(primaryRay(camera, vec2(x, y) + corner)).hit();
      covered->at<uchar>(y, x) = all ? 255 : 0;
    }
  return renderPathTraced(tracer, camera, spp, stats);
}

TEST(Dielectric, SmoothGlassSphereInAWhiteFurnaceIsInvisible) {
  cv::Mat covered;
  const cv::Mat image = furnace(glass(1.5f), 32, &covered);
  int pixels = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      if (!covered.at<uchar>(y, x)) continue;
      ++pixels;
      const vec3 v = rgbAt(image, x, y);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[c], 1.0f, 0.01f) << x << "," << y;
    }
  EXPECT_GT(pixels, 150);
}

TEST(Dielectric, RoughGlassSphereInAWhiteFurnaceLosesLittle) {
  cv::Mat covered;
  // Single-scattering microfacets lose what scatters more than once (about 3% on average at
  // roughness 0.3, more towards the rim).
  const cv::Mat image = furnace(glass(1.5f, 0.3f), 256, &covered, nullptr, 12);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      if (!covered.at<uchar>(y, x)) continue;
      const float v = rgbAt(image, x, y).y;
      EXPECT_GE(v, 0.9f) << x << "," << y;
      EXPECT_LE(v, 1.0f + 0.02f) << x << "," << y;  // 256 spp of noise above the bound
    }
}

// IOR 1: the interface is invisible and the pixel is exactly the environment behind, also
// through a thin wall.
TEST(Dielectric, IndexOneShowsTheEnvironmentBehind) {
  cv::Mat pano(64, 128, CV_32FC3);
  for (int y = 0; y < pano.rows; ++y)
    for (int x = 0; x < pano.cols; ++x) {
      const vec3 d = equirect::uvToDirection({(x + 0.5f) / pano.cols, (y + 0.5f) / pano.rows});
      setRgb(pano, x, y, vec3(0.5f + 0.5f * d.x, 0.2f + 0.1f * d.y, 1.0f - 0.5f * d.z));
    }
  const Environment env(pano);
  for (const bool thin : {false, true}) {
    SurfaceMaterial m = glass(1.0f, 0.4f);  // roughness does not matter without index contrast
    m.thin_walled = thin;
    RenderScene scene(test::sphereModel(m), {});
    scene.overrideRelicMaterial(m);
    const PathTracer tracer(scene, env);
    for (const vec3 target : {vec3(0.0f), vec3(0.3f, 0.5f, 0.0f), vec3(-0.6f, -0.2f, 0.1f)}) {
      const Ray ray{{0, 0, 4}, glm::normalize(target - vec3(0, 0, 4))};
      const vec3 L = meanAlong(tracer, ray, 16);
      const vec3 behind = env.radiance(ray.direction);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(L[c], behind[c], 1e-4f) << thin;
    }
  }
}

// Uniform directions on the sphere from a fixed seed.
vec3 uniformDirection(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float z = 1.0f - 2.0f * u(rng), phi = 2.0f * kPi * u(rng);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Seen from side A (normal +Z, IOR 1) and from side B (normal -Z, IOR eta): the same interface.
struct Interface {
  DielectricBsdf above, below;
  Interface(float eta, float roughness)
      : above(glass(eta, roughness), {0, 0, 1}, eta, vec3(1.0f), false),
        below(glass(eta, roughness), {0, 0, -1}, 1.0f / eta, vec3(1.0f), false) {}
  // f(wo, wi) with wo's side choosing the view; eval() returns f |cos theta_i|.
  float f(const vec3& wo, const vec3& wi) const {
    const DielectricBsdf& side = wo.z > 0.0f ? above : below;
    return side.eval(wo, wi).y / std::abs(wi.z);
  }
};

TEST(Dielectric, RoughTransmissionIsReciprocalInTheGeneralisedSense) {
  std::mt19937 rng(7);
  for (const float eta : {1.5f, 2.42f})
    for (const float roughness : {0.2f, 0.6f, 1.0f}) {
      const Interface glass_interface(eta, roughness);
      int compared = 0;
      for (int i = 0; i < 4000 && compared < 400; ++i) {
        vec3 o = uniformDirection(rng), in = uniformDirection(rng);
        if (std::abs(o.z) < 0.05f || std::abs(in.z) < 0.05f) continue;
        const float n_o = o.z > 0.0f ? 1.0f : eta, n_i = in.z > 0.0f ? 1.0f : eta;
        const float forward = glass_interface.f(o, in), backward = glass_interface.f(in, o);
        if (forward < 1e-4f && backward < 1e-4f) continue;
        ++compared;
        // f(i, o) / n_o^2 = f(o, i) / n_i^2 (Veach 1997, 5.2), both sides and both lobes.
        EXPECT_NEAR(forward / (n_o * n_o), backward / (n_i * n_i), 2e-3f * (forward / (n_o * n_o)) + 1e-6f)
            << "eta " << eta << " roughness " << roughness;
      }
      EXPECT_GT(compared, 100);
    }
}

// Light arriving along wi (from above): the flux fraction it leaves with, f(wo, wi) |cos wo|
// integrated over every wo (both sides), is at most 1, and the rough interface keeps most of it.
TEST(Dielectric, RoughInterfaceScattersAtMostTheFluxItReceives) {
  std::mt19937 rng(11);
  for (const float eta : {1.5f, 2.42f})
    for (const float roughness : {0.1f, 0.5f, 1.0f})
      for (const float theta_deg : {0.0f, 45.0f, 80.0f})
        for (const bool from_inside : {false, true}) {
          const Interface glass_interface(eta, roughness);
          const float t = glm::radians(theta_deg);
          const vec3 wi(std::sin(t), 0.0f, from_inside ? -std::cos(t) : std::cos(t));
          constexpr int kN = 100000;
          double sum = 0.0, sum2 = 0.0;
          for (int k = 0; k < kN; ++k) {
            const vec3 wo = uniformDirection(rng);
            // Radiance L f |cos_o| d(omega_o) is flux: the étendue n^2 cos d(omega) that refraction
            // conserves is already in f's (n_o / n_i)^2, so no index appears here.
            const double v = glass_interface.f(wo, wi) * std::abs(wo.z) * 4.0 * kPi;
            sum += v;
            sum2 += v * v;
          }
          const double mean = sum / kN;
          const double err = std::sqrt(std::max(0.0, sum2 / kN - mean * mean) / kN);
          SCOPED_TRACE(::testing::Message() << "eta " << eta << " roughness " << roughness << " theta "
                                            << theta_deg << (from_inside ? " inside" : " outside"));
          EXPECT_LE(mean, 1.0 + 3.0 * err + 1e-3);
          // (Uniform directions estimate a sharper lobe's integral too noisily for a lower bound.)
          if (roughness == 0.5f) {
            EXPECT_GE(mean, 0.8);
          }
        }
}

// The glTF mixture (clearcoat over metal, opaque dielectric and rough glass) samples what it
// evaluates: the mean sample weight equals the integral of eval() over the sphere, estimated
// here with uniform directions.
TEST(Dielectric, MaterialMixtureSamplesWhatItEvaluates) {
  SurfaceMaterial m = glass(1.5f, 0.5f);
  m.base_colour = vec3(0.9f, 0.7f, 0.5f);
  m.metallic = 0.2f;
  m.transmission = 0.6f;
  m.clearcoat = 0.7f;
  m.clearcoat_roughness = 0.4f;
  for (const bool front : {true, false})
    for (const float theta_deg : {10.0f, 60.0f}) {
      SCOPED_TRACE(::testing::Message() << (front ? "outside" : "inside") << " theta " << theta_deg);
      const MaterialBsdf bsdf(m, {0, 0, 1}, front);
      const float t = glm::radians(theta_deg);
      const vec3 wo(std::sin(t), 0.0f, std::cos(t));
      std::mt19937 rng(3);
      std::uniform_real_distribution<float> u(0.0f, 0.99999f);
      constexpr int kN = 200000;
      double sampled = 0.0, integral = 0.0;
      for (int k = 0; k < kN; ++k) {
        if (const auto s = bsdf.sample(wo, {u(rng), u(rng), u(rng)})) {
          ASSERT_FALSE(s->delta);
          sampled += s->weight.y;
          // The pdf a sample reports is the one pdf() gives for its direction.
          if (k % 1000 == 0) {
            EXPECT_NEAR(s->pdf, bsdf.pdf(wo, s->wi), 1e-3f * s->pdf);
          }
        }
        integral += bsdf.eval(wo, uniformDirection(rng)).y * 4.0 * kPi;
      }
      EXPECT_NEAR(sampled / kN, integral / kN, 0.02 * (integral / kN));
    }
}

// Hostile but legal materials: finite output in range, whatever the IOR, roughness, absorption.
TEST(Dielectric, HostileMaterialsStayFiniteAndInRange) {
  struct Case {
    const char* what;
    SurfaceMaterial m;
  };
  std::vector<Case> cases;
  for (const float ior : {1.0f, 1.0001f, 2.42f, 3.0f}) cases.push_back({"ior", glass(ior)});
  cases.push_back({"roughness 1", glass(1.5f, 1.0f)});
  cases.push_back({"roughness 0 at IOR 1.0001", glass(1.0001f, 0.0f)});
  cases.push_back({"rough IOR 1.0001", glass(1.0001f, 0.5f)});
  SurfaceMaterial dense = glass(1.5f);
  dense.attenuation_colour = vec3(0.2f, 0.5f, 0.0f);
  dense.attenuation_distance = 1e-6f;
  cases.push_back({"attenuation distance 1e-6", dense});
  SurfaceMaterial clear = glass(1.5f);
  clear.attenuation_colour = vec3(0.2f, 0.5f, 0.9f);
  clear.attenuation_distance = 3e38f;
  cases.push_back({"attenuation distance huge", clear});
  SurfaceMaterial thin = glass(1.5f, 0.3f);
  thin.thin_walled = true;  // thickness 0
  cases.push_back({"thin-walled", thin});
  SurfaceMaterial layered = glass(1.5f, 0.2f);
  layered.transmission = 0.5f;
  layered.clearcoat = 1.0f;
  layered.clearcoat_roughness = 0.0f;
  layered.specular = 0.3f;
  layered.specular_colour = vec3(2.0f, 0.5f, 1.0f);
  cases.push_back({"half transmissive, clearcoat, specular", layered});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    cv::Mat covered;
    PathTracerStats stats;
    const cv::Mat image = furnace(c.m, 8, &covered, &stats, 12);
    EXPECT_EQ(stats.nonfinite_dropped, 0);
    for (int y = 0; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x) {
        const vec3 v = rgbAt(image, x, y);
        ASSERT_TRUE(isFinite(v));
        for (int k = 0; k < 3; ++k) {
          EXPECT_GE(v[k], 0.0f);
          // A white furnace of 1; one path sample can exceed 1 (each vertex adds its MIS share).
          EXPECT_LE(v[k], 2.5f);
        }
      }
  }
  // Grazing incidence on a glass sphere, exactly tangent and just inside.
  RenderScene scene(test::sphereModel(glass(2.42f)), {});
  scene.overrideRelicMaterial(glass(2.42f, 0.0f));
  const Environment env = Environment::uniform(vec3(1.0f));
  const PathTracer tracer(scene, env);
  for (const float x : {0.999f, 0.99999f}) {
    const vec3 L = meanAlong(tracer, {{x, 0.0f, 4.0f}, {0, 0, -1}}, 64);
    EXPECT_TRUE(isFinite(L));
    EXPECT_LE(L.y, 1.0f + 1e-4f);
  }
}

// Rays trapped by total internal reflection in a high-index cube stop at the bounce cap, and the
// energy they still carried is reported: pixel + truncated throughput is the white furnace's 1
// (smooth, non-absorbing glass: every path that leaves does so with weight 1).
TEST(Dielectric, TrappedRaysStopAtTheCapWithTheirEnergyAccounted) {
  RenderScene scene(boxModel({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}), {});
  scene.overrideRelicMaterial(glass(3.0f));
  const Environment env = Environment::uniform(vec3(1.0f));
  PathTracerOptions options;
  options.max_dielectric_bounces = 6;
  const PathTracer tracer(scene, env, options);
  constexpr int kN = 2048;
  {
    // From inside along a diagonal: every face is met at 54.7 degrees, beyond the critical angle
    // (19.5 degrees at IOR 3), so the ray never leaves.
    std::int64_t truncated = 0;
    double truncated_throughput = 0.0;
    const vec3 L = meanAlong(tracer, {{0.1f, -0.05f, 0.0f}, glm::normalize(vec3(1.0f, 1.0f, 1.0f))}, kN,
                             &truncated, &truncated_throughput);
    EXPECT_EQ(truncated, kN);
    EXPECT_LT(luminance(L), 1e-6f);
    EXPECT_NEAR(truncated_throughput / kN, 1.0, 1e-4);
  }
  {
    // From outside, obliquely: some paths reflect inside more than the cap allows.
    std::int64_t truncated = 0;
    double truncated_throughput = 0.0;
    const vec3 L = meanAlong(tracer, {{-0.8f, 1.5f, 0.1f}, glm::normalize(vec3(0.6f, -1.0f, 0.05f))}, kN,
                             &truncated, &truncated_throughput);
    EXPECT_GT(truncated, 0);
    EXPECT_NEAR(L.y + truncated_throughput / kN, 1.0, 1e-3);
  }
}

// NaN or negative factors in a file are an InputError naming the material and the field.
TEST(Dielectric, BadVolumeFactorsInAFileAreInputErrors) {
  const auto dir = test::scratchDir("dielectric_gltf");
  Model model = boxModel({-1, -1, -1}, {1, 1, 1});
  model.materials[0].name = "bad_glass";
  model.materials[0].transmission = 1.0f;
  model.materials[0].thickness = 0.5f;
  model.materials[0].attenuation_distance = 0.25f;
  model.materials[0].ior = 1.25f;
  model.materials[0].clearcoat = 0.5f;
  model.materials[0].specular_colour = vec3(0.5f);
  saveGltf(dir / "glass.gltf", model);
  std::stringstream text;
  text << std::ifstream(dir / "glass.gltf").rdbuf();
  const std::string good = text.str();
  struct Bad {
    std::string field, value;
  };
  // (NaN and infinities have no JSON spelling: the parser rejects "1e999" as an invalid file.)
  for (const Bad& bad :
       {Bad{"transmissionFactor", "-0.5"}, Bad{"thicknessFactor", "-1"}, Bad{"attenuationDistance", "0"},
        Bad{"attenuationDistance", "-2"}, Bad{"attenuationColor", "[0.5, -0.1, 1]"}, Bad{"ior", "0.5"},
        Bad{"clearcoatFactor", "-1"}, Bad{"specularColorFactor", "[1, -1, 1]"}}) {
    SCOPED_TRACE(bad.field + " = " + bad.value);
    // Replace the value after "field": (a number or an array) in the writer's JSON.
    std::string edited = good;
    const auto key = edited.find("\"" + bad.field + "\"");
    ASSERT_NE(key, std::string::npos) << good;
    const auto start = edited.find(':', key) + 1;
    const auto end = edited[edited.find_first_not_of(" \n", start)] == '['
                         ? edited.find(']', start) + 1
                         : edited.find_first_of(",\n}", start);
    edited.replace(start, end - start, " " + bad.value);
    std::ofstream(dir / "bad.gltf") << edited;
    try {
      (void)loadGltf(dir / "bad.gltf");
      ADD_FAILURE() << "loaded";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("bad_glass"), std::string::npos) << what;
      EXPECT_NE(what.find(bad.field), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace holo::reference

namespace holo::reference {
namespace {

// The built-in glass relics are closed volumes as the tracer sees them: with their absorption
// off, in a white furnace every path that leaves does so with weight 1, so along every ray that
// meets the relic, radiance + the energy the bounce cap stopped is 1 (within 1%). A crossing the
// tracer got wrong (a wall entered twice, a facet wound inwards, a refraction sent back out by a
// smoothed normal across a crease) would leave a factor n^2 in the weight.
TEST(Dielectric, GlassRelicsInAWhiteFurnaceAreInvisible) {
  for (const std::string name : {"glass-vase", "crystal"}) {
    SCOPED_TRACE(name);
    Model relic = relics::makeRelic(name);
    relic.materials[0].attenuation_distance = std::numeric_limits<float>::infinity();
    relic.materials[0].base_colour = vec3(1.0f);
    RenderScene scene(relic, {});
    const Environment env = Environment::uniform(vec3(1.0f));
    const PathTracer tracer(scene, env);
    const vec3 centre = relic.bounds().center();
    const CameraModel camera = lookAtCamera(centre + vec3(0.0f, 0.25f, 0.8f), centre, 24.0f, 24, 24);
    int rays = 0;
    for (int y = 0; y < camera.height(); ++y)
      for (int x = 0; x < camera.width(); ++x) {
        const Ray ray = primaryRay(camera, vec2(x, y));
        const RayHit hit = scene.relicOnly().intersect(ray);
        if (!hit.hit()) continue;
        ++rays;
        double energy = 0.0;
        constexpr int kSpp = 16;
        for (int i = 0; i < kSpp; ++i) {
          SampleStream stream(9, std::uint32_t(y * camera.width() + x), std::uint32_t(i));
          PathRecord record;
          energy +=
              double(tracer.traceFromRelic(ray, hit, stream, 0.0f, &record).y) + record.truncated_throughput;
        }
        EXPECT_NEAR(energy / kSpp, 1.0, 0.01) << x << "," << y;
      }
    EXPECT_GT(rays, 50);
  }
}

}  // namespace
}  // namespace holo::reference
