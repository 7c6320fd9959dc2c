// The hall panorama at a finite distance: a reflection ray from a point away from where the
// panorama was captured meets the proxy sphere and reads the direction from the capture point
// to that meeting point (parallax), in the live renderer's IBL lookup and in the path tracer's
// environment alike; the pdfs stay consistent so the path tracer stays unbiased; the default
// (infinite) proxy changes nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/reference/sampler.hpp"
#include "holo/reflect/environment.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"

namespace holo::reflect {
namespace {

using reference::SampleStream;

// Every pixel a different colour: red = longitude, green = colatitude, so a lookup tells which
// pixel it read.
cv::Mat codedPanorama(int width = 256, int height = 128) {
  cv::Mat pano(height, width, CV_32FC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      pano.at<cv::Vec3f>(y, x) =
          cv::Vec3f(0.2f, (float(y) + 0.5f) / float(height), (float(x) + 0.5f) / float(width));
  return pano;
}

// The integral of environment.pdf(origin, .) over the sphere of directions (Monte Carlo, 20000
// uniform directions).
double pdfOverTheSphere(const Environment& environment, const vec3& origin) {
  double integral = 0.0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    SampleStream stream(9, 0, std::uint32_t(i));
    const vec2 u = stream.next2D();
    const float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * u.y;
    integral += double(environment.pdf(origin, vec3(r * std::cos(phi), r * std::sin(phi), z))) * 4.0 * kPi;
  }
  return integral / n;
}

TEST(PanoramaProxy, OffCentreReflectionRayReadsTheDirectionToWhereItMeetsTheHall) {
  // A hall of 10 m radius captured 1 m above the pyramid's origin; a point on the relic 0.3 m
  // beside the capture point looks straight along +Z.
  const PanoramaProxy proxy{{0.0f, 1.0f, 0.0f}, 10.0f};
  const vec3 origin{0.3f, 1.0f, 0.0f};
  const vec3 direction{0.0f, 0.0f, 1.0f};
  // Meets the sphere at (0.3, 1, sqrt(100 - 0.09)): seen from the capture point at
  // atan(0.3 / 9.9955) = 1.719 degrees towards +X.
  const vec3 expected = glm::normalize(vec3(0.3f, 0.0f, std::sqrt(100.0f - 0.09f)));
  const vec3 looked_up = proxy.lookupDirection(origin, direction);
  EXPECT_NEAR(glm::length(looked_up - expected), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::degrees(std::acos(glm::dot(looked_up, direction))), 1.719f, 0.002f);
  // From the capture point itself, and for an infinite hall, no parallax.
  EXPECT_NEAR(glm::length(proxy.lookupDirection(proxy.centre, direction) - direction), 0.0f, 1e-6f);
  EXPECT_EQ(PanoramaProxy{}.lookupDirection(origin, direction), direction);
  // Parallax grows with the distance from the capture point: 5 m off, the same ray meets the
  // wall at (5, 1, 8.66), 30 degrees off +Z seen from the capture point.
  const vec3 far_point{5.0f, 1.0f, 0.0f};
  const vec3 side = proxy.lookupDirection(far_point, glm::normalize(vec3(0.0f, 0.0f, 1.0f)));
  EXPECT_NEAR(glm::degrees(std::acos(glm::dot(side, direction))), glm::degrees(std::asin(0.5f)), 1e-3f);

  // The environment reads the pixel of the looked-up direction: 1.7 degrees is 1.2 pixels of a
  // 256-wide panorama, so the two pixels differ.
  const Environment environment(codedPanorama(), 0.0f, proxy);
  EXPECT_EQ(environment.radiance(origin, direction), environment.radiance(looked_up));
  EXPECT_NE(environment.radiance(origin, direction), environment.radiance(direction));
  const Environment at_infinity(codedPanorama());
  EXPECT_EQ(at_infinity.radiance(origin, direction), at_infinity.radiance(direction));

  // The live renderer's IBL: a mirror at `origin` reflecting along +Z reads the mirror level at
  // the looked-up direction, not at +Z.
  const PrefilteredIbl ibl(environment, PrefilterOptions{3, 64, 8});
  const SurfaceMaterial mirror{vec3(1.0f), 1.0f, 0.0f, 1.0f};
  const vec3 normal{0.0f, 0.0f, 1.0f};
  const SplitSumShading at_point = ibl.shadeParts(mirror, normal, direction, direction, origin);
  EXPECT_NEAR(glm::length(at_point.environment - ibl.specular(looked_up, 0.0f)), 0.0f, 1e-6f);
  // A point 5 m off reads a clearly different colour than the capture point would.
  const SplitSumShading off = ibl.shadeParts(mirror, normal, direction, direction, far_point);
  const SplitSumShading centre = ibl.shadeParts(mirror, normal, direction, direction, proxy.centre);
  EXPECT_GT(std::abs(off.environment.r - centre.environment.r), 0.05f);  // 30 degrees of longitude
}

TEST(PanoramaProxy, SamplingPdfsStayConsistentForThePathTracer) {
  const Environment environment(codedPanorama(64, 32), 0.3f, PanoramaProxy{{0.0f, 1.5f, 0.0f}, 6.0f});
  const vec3 origin{0.4f, 0.2f, -0.3f};
  // sample() and pdf() agree, and the pdf integrates to 1 over the sphere of directions at
  // `origin` (Monte Carlo over uniform directions, 20000 samples).
  for (int i = 0; i < 200; ++i) {
    SampleStream stream(5, 0, std::uint32_t(i));
    const EnvironmentSample s = environment.sample(stream.next2D(), origin);
    ASSERT_GT(s.pdf, 0.0f);
    EXPECT_NEAR(glm::length(s.direction), 1.0f, 1e-5f);
    EXPECT_NEAR(environment.pdf(origin, s.direction), s.pdf, 2e-3f * s.pdf);
    EXPECT_EQ(environment.radiance(origin, s.direction), s.radiance);
  }
  EXPECT_NEAR(pdfOverTheSphere(environment, origin), 1.0, 0.03);
}

// The pyramid's base (top at y = 0, half width 0.3 m) lies nearer than the hall below a relic: a
// ray from a point on the relic down onto it reads the direction from the capture point to where
// it meets the base, not the hall's sphere beyond; a ray past the base's edge reads the sphere;
// the pdfs stay consistent with the base too (a pixel the base hides from the point is not drawn),
// and the pdf integrates to the share of samples drawn within 3%.
TEST(PanoramaProxy, TheBaseBelowTheRelicHidesTheHallBehindIt) {
  PanoramaProxy proxy{{0.0f, 0.35f, 0.0f}, 4.0f, 0.3f};
  const vec3 origin{0.1f, 0.05f, 0.0f};
  const vec3 down = glm::normalize(vec3(0.5f, -1.0f, 0.2f));
  const vec3 on_base = origin + (0.05f / 1.0f) * glm::length(vec3(0.5f, -1.0f, 0.2f)) * down;
  ASSERT_NEAR(on_base.y, 0.0f, 1e-5f);
  const vec3 expected = glm::normalize(on_base - proxy.centre);
  EXPECT_LT(glm::length(proxy.lookupDirection(origin, down) - expected), 1e-5f);
  EXPECT_LT(glm::length(proxy.point(expected) - on_base), 1e-4f);
  const vec3 past = glm::normalize(vec3(1.0f, -0.1f, 0.0f));  // meets y = 0 at x = 0.6: past the edge
  PanoramaProxy no_base = proxy;
  no_base.base_half_width = 0.0f;
  EXPECT_LT(glm::length(proxy.lookupDirection(origin, past) - no_base.lookupDirection(origin, past)), 1e-6f);
  EXPECT_GT(glm::length(proxy.lookupDirection(origin, down) - no_base.lookupDirection(origin, down)), 0.1f);

  const Environment environment(codedPanorama(64, 32), 0.0f, proxy);
  int drawn = 0;
  const int samples = 4000;
  for (int i = 0; i < samples; ++i) {
    SampleStream stream(5, 0, std::uint32_t(i));
    const EnvironmentSample s = environment.sample(stream.next2D(), origin);
    if (!(s.pdf > 0.0f)) continue;  // a pixel the base hides from the origin
    ++drawn;
    EXPECT_NEAR(environment.pdf(origin, s.direction), s.pdf, 2e-3f * s.pdf);
  }
  EXPECT_GT(drawn, samples / 2);
  // The pdf integrates to the share of samples drawn.
  EXPECT_NEAR(pdfOverTheSphere(environment, origin), double(drawn) / samples, 0.03);
}

TEST(PanoramaProxy, BadProxyIsAnInputError) {
  EXPECT_THROW(Environment(codedPanorama(16, 8), 0.0f, PanoramaProxy{{0.0f, 0.0f, 0.0f}, 0.0f}), InputError);
  EXPECT_THROW(Environment(codedPanorama(16, 8), 0.0f, PanoramaProxy{{NAN, 0.0f, 0.0f}, 5.0f}), InputError);
  EXPECT_THROW(Environment(codedPanorama(16, 8), 0.0f, PanoramaProxy{{0.0f, 0.0f, 0.0f}, 5.0f, -0.1f}),
               InputError);
}

}  // namespace
}  // namespace holo::reflect
