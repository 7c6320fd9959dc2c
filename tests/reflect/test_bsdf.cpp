// The relic's BSDF: GGX normalisation, energy bounds, sampling consistent with eval, and the hard
// cases (grazing angles, roughness 0 and 1, directions below the surface).
#include <gtest/gtest.h>

#include <cmath>

#include "holo/reference/sampler.hpp"
#include "holo/reflect/bsdf.hpp"
#include "holo/reflect/dfg_table.hpp"

namespace holo::reflect {
namespace {

using reference::SampleStream;

// Midpoint quadrature of g(wi) over the upper hemisphere (theta x phi grid).
template <class F>
double hemisphereIntegral(F g, int n_theta = 256, int n_phi = 512) {
  double sum = 0;
  for (int i = 0; i < n_theta; ++i) {
    const double theta = (i + 0.5) / n_theta * 0.5 * M_PI;
    const double dw = std::sin(theta) * (0.5 * M_PI / n_theta) * (2 * M_PI / n_phi);
    for (int j = 0; j < n_phi; ++j) {
      const double phi = (j + 0.5) / n_phi * 2 * M_PI;
      const vec3 wi(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                    float(std::cos(theta)));
      sum += g(wi) * dw;
    }
  }
  return sum;
}

vec3 fromCos(float c) {
  return {std::sqrt(std::max(0.0f, 1 - c * c)), 0.0f, c};
}

TEST(Ggx, DistributionIsNormalised) {
  for (float alpha : {0.05f, 0.3f, 1.0f}) {
    const double integral =
        hemisphereIntegral([&](const vec3& h) { return ggx::D(h.z, alpha) * h.z; }, 2048, 16);
    EXPECT_NEAR(integral, 1.0, 2e-3) << "alpha " << alpha;
  }
}

TEST(Ggx, MaskingIsBoundedAndHeightCorrelated) {
  for (float alpha : {0.01f, 0.5f, 1.0f})
    for (float co : {1e-6f, 0.1f, 0.7f, 1.0f})
      for (float ci : {1e-6f, 0.3f, 1.0f}) {
        const float g2 = ggx::G2(co, ci, alpha);
        EXPECT_GE(g2, 0.0f);
        EXPECT_LE(g2, std::min(ggx::G1(co, alpha), ggx::G1(ci, alpha)) + 1e-6f);
      }
  EXPECT_FLOAT_EQ(ggx::G2(1.0f, 1.0f, 0.7f), 1.0f);
}

TEST(Bsdf, WhiteMetalAlbedoMatchesDfgAndNeverExceedsOne) {
  // F0 = 1: the directional albedo is the DFG sum A + B; by quadrature of eval() it must agree
  // with the visible-normal estimate (independent code paths) and stay <= 1. At cos 0.05 the
  // lobe hugs the horizon and is only ~0.02 rad wide in azimuth, hence the fine phi grid.
  for (float roughness : {0.3f, 0.6f, 1.0f})
    for (float c : {0.05f, 0.4f, 1.0f}) {
      const Bsdf bsdf({vec3(1.0f), 1.0f, roughness, 1.0f}, vec3(0, 0, 1));
      const vec3 wo = fromCos(c);
      const double albedo =
          hemisphereIntegral([&](const vec3& wi) { return bsdf.eval(wo, wi).x; }, 512, 4096);
      const vec2 ab = dfgIntegrate(c, roughness, 1 << 14);
      EXPECT_NEAR(albedo, ab.x + ab.y, 0.005) << "roughness " << roughness << " cos " << c;
      EXPECT_LE(albedo, 1.0 + 1e-3);
    }
}

TEST(Bsdf, SampleWeightsAreEvalOverPdf) {
  // E[weight] over samples = albedo (quadrature of eval), for a mixed dielectric material.
  const SurfaceMaterial m{vec3(0.7f, 0.5f, 0.3f), 0.3f, 0.4f, 1.0f};
  const Bsdf bsdf(m, vec3(0, 0, 1));
  for (float c : {0.2f, 0.9f}) {
    const vec3 wo = fromCos(c);
    const double albedo = hemisphereIntegral([&](const vec3& wi) { return bsdf.eval(wo, wi).y; });
    double sum = 0;
    const int n = 1 << 15;
    for (int i = 0; i < n; ++i) {
      SampleStream s(7, 0, std::uint32_t(i));
      const auto bs = bsdf.sample(wo, s.next3D());
      if (!bs) continue;
      EXPECT_NEAR(bs->pdf, bsdf.pdf(wo, bs->wi), 1e-3f * bs->pdf);
      sum += bs->weight.y;
    }
    EXPECT_NEAR(sum / n, albedo, 0.005 * albedo) << "cos " << c;
  }
}

TEST(Bsdf, RoughnessZeroIsAnExactMirror) {
  const Bsdf bsdf({vec3(1.0f), 1.0f, 0.0f, 1.0f}, glm::normalize(vec3(0.2f, 1.0f, 0.1f)));
  const vec3 wo = glm::normalize(vec3(-0.4f, 0.6f, 0.3f));
  const auto s = bsdf.sample(wo, vec3(0.3f, 0.5f, 0.5f));
  ASSERT_TRUE(s.has_value());
  EXPECT_TRUE(s->delta);
  const vec3 expected = glm::reflect(-wo, bsdf.normal());
  EXPECT_NEAR(glm::length(s->wi - expected), 0.0f, 1e-5f);
  EXPECT_NEAR(s->weight.x, 1.0f, 1e-6f);  // F0 = 1
  // The delta lobe is invisible to eval and pdf: no huge finite lobe.
  EXPECT_EQ(bsdf.eval(wo, expected), vec3(0.0f));
  EXPECT_EQ(bsdf.pdf(wo, expected), 0.0f);
}

TEST(Bsdf, HardCasesStayFinite) {
  const vec3 n(0, 0, 1);
  const std::vector<vec3> dirs = {fromCos(1.0f),  fromCos(1e-7f), fromCos(0.0f),
                                  fromCos(-0.3f), vec3(0, 0, -1), glm::normalize(vec3(1, 1, 1e-8f))};
  for (float roughness : {0.0f, 0.005f, 0.01f, 0.5f, 1.0f})
    for (float metallic : {0.0f, 1.0f}) {
      const Bsdf bsdf({vec3(0.9f), metallic, roughness, 1.0f}, n);
      for (const vec3& wo : dirs) {
        for (const vec3& wi : dirs) {
          EXPECT_TRUE(isFinite(bsdf.eval(wo, wi)));
          EXPECT_TRUE(std::isfinite(bsdf.pdf(wo, wi)));
          EXPECT_GE(bsdf.pdf(wo, wi), 0.0f);
        }
        for (int i = 0; i < 64; ++i) {
          SampleStream s(3, 1, std::uint32_t(i));
          const auto bs = bsdf.sample(wo, s.next3D());
          if (!bs) continue;
          EXPECT_TRUE(isFinite(bs->weight) && isFinite(bs->wi) && std::isfinite(bs->pdf));
          EXPECT_LE(luminance(bs->weight), 20.0f);
        }
      }
      // Facing away (view below the shading hemisphere): scatters nothing, finitely.
      EXPECT_FALSE(bsdf.sample(fromCos(-0.5f), vec3(0.5f)).has_value());
    }
}

TEST(Bsdf, TheDielectricF0FollowsTheIorAndTheSpecularColour) {
  // KHR_materials_ior + KHR_materials_specular: F0 = min(((n - 1) / (n + 1))^2 colour, 1).
  const auto closed = [](double n) { return float(((n - 1) / (n + 1)) * ((n - 1) / (n + 1))); };
  EXPECT_EQ(dielectricF0(1.5f, vec3(1.0f)), vec3(kDielectricF0));  // the defaults: exactly 0.04
  EXPECT_EQ(dielectricF0(2.0f, vec3(1.0f)), vec3(closed(2.0)));
  EXPECT_EQ(dielectricF0(1.0f, vec3(1.0f)), vec3(0.0f));
  const vec3 tinted = dielectricF0(2.0f, vec3(1.0f, 0.5f, 0.0f));
  EXPECT_FLOAT_EQ(tinted.r, closed(2.0));
  EXPECT_FLOAT_EQ(tinted.g, 0.5f * closed(2.0));
  EXPECT_EQ(tinted.b, 0.0f);
  // Out of range: clamped to [0,1], never NaN.
  EXPECT_EQ(dielectricF0(1e30f, vec3(1.0f)), vec3(1.0f));
  EXPECT_EQ(dielectricF0(INFINITY, vec3(1.0f)), vec3(1.0f));
  EXPECT_EQ(dielectricF0(2.0f, vec3(100.0f)), vec3(1.0f));
  EXPECT_EQ(dielectricF0(0.5f, vec3(1.0f)), vec3(0.0f));
  EXPECT_EQ(dielectricF0(NAN, vec3(1.0f)), vec3(kDielectricF0));
  EXPECT_EQ(dielectricF0(INFINITY, vec3(NAN, -1.0f, INFINITY)), vec3(0.0f, 0.0f, 1.0f));
}

TEST(Bsdf, TheIorAndSpecularColourSetTheMirrorsReflectanceAndTheDiffuseKeepsTheRest) {
  // A smooth black dielectric seen head-on reflects F0 of its IOR, per colour channel.
  const auto mirror = [](float ior, const vec3& colour, const vec3& base) {
    SurfaceMaterial m{base, 0.0f, 0.0f, 1.0f};
    m.ior = ior;
    m.specular_colour = colour;
    const Bsdf bsdf(m, vec3(0, 0, 1));
    // u.x = 0 picks the specular lobe, the only one on a black base.
    const auto s = bsdf.sample(vec3(0, 0, 1), vec3(0.0f, 0.5f, 0.5f));
    return s && s->delta ? s->weight : vec3(-1.0f);
  };
  EXPECT_NEAR(mirror(2.0f, vec3(1.0f), vec3(0.0f)).g, 1.0f / 9.0f, 1e-6f);
  EXPECT_NEAR(mirror(1.5f, vec3(1.0f), vec3(0.0f)).g, 0.04f, 1e-7f);
  const vec3 red = mirror(2.0f, vec3(1.0f, 0.0f, 0.0f), vec3(0.0f));
  EXPECT_NEAR(red.r, 1.0f / 9.0f, 1e-6f);
  EXPECT_EQ(red.g, 0.0f);
  // Energy: a white diffuse base under a red F0 of 1 keeps nothing (1 - max over RGB of F), and
  // a rough coloured lobe over white never reflects more than comes in.
  for (const float roughness : {0.3f, 0.8f}) {
    SurfaceMaterial m{vec3(1.0f), 0.0f, roughness, 1.0f};
    m.ior = 3.0f;
    m.specular_colour = vec3(4.0f, 1.0f, 0.0f);
    const Bsdf bsdf(m, vec3(0, 0, 1));
    for (const float c : {0.2f, 0.9f}) {
      const vec3 wo = fromCos(c);
      for (int k = 0; k < 3; ++k) {
        const double albedo = hemisphereIntegral([&](const vec3& wi) { return bsdf.eval(wo, wi)[k]; });
        EXPECT_LE(albedo, 1.0 + 2e-3) << "channel " << k << " roughness " << roughness << " cos " << c;
      }
    }
  }
  // A white Lambert base under a smooth coat whose red F0 is clamped to 1: nothing is left for
  // the diffuse in any channel (eval sees only the diffuse of a mirror).
  SurfaceMaterial saturated{vec3(1.0f), 0.0f, 0.0f, 1.0f};
  saturated.ior = 2.0f;
  saturated.specular_colour = vec3(10.0f, 0.0f, 0.0f);
  const Bsdf bsdf(saturated, vec3(0, 0, 1));
  EXPECT_EQ(bsdf.eval(fromCos(0.7f), fromCos(0.3f)), vec3(0.0f));
}

TEST(Dfg, TableMatchesDirectIntegration) {
  for (float r : {0.1f, 0.37f, 0.8f})
    for (float c : {0.1f, 0.5f, 0.95f}) {
      const vec2 t = dfg(c, r), d = dfgIntegrate(c, r, 4096);
      EXPECT_NEAR(t.x, d.x, 0.02f);
      EXPECT_NEAR(t.y, d.y, 0.01f);
    }
}

}  // namespace
}  // namespace holo::reflect
