#include <gtest/gtest.h>

#include "holo/core/texture.hpp"

namespace holo {
namespace {

// A one-row image of the given grey levels (BGR, 8 bits).
cv::Mat row(std::initializer_list<int> greys) {
  cv::Mat m(1, static_cast<int>(greys.size()), CV_8UC3);
  int x = 0;
  for (int g : greys) m.at<cv::Vec3b>(0, x++) = cv::Vec3b(uchar(g), uchar(g), uchar(g));
  return m;
}

TextureSampler wrapBoth(TextureWrap wrap) {
  TextureSampler s;
  s.wrap_u = s.wrap_v = wrap;
  return s;
}

TEST(Texture, MipChainHalvesDownToOneTexelAndKeepsTheMean) {
  cv::Mat image(3, 5, CV_8UC3, cv::Scalar(40, 80, 120));
  const Texture t(image);
  ASSERT_EQ(t.levels.size(), 4u);  // 5x3, 3x2, 2x1, 1x1
  EXPECT_EQ(t.levels[1].size(), cv::Size(3, 2));
  EXPECT_EQ(t.levels[2].size(), cv::Size(2, 1));
  EXPECT_EQ(t.levels[3].size(), cv::Size(1, 1));
  EXPECT_EQ(t.levels[3].at<cv::Vec3b>(0, 0), cv::Vec3b(40, 80, 120));
  cv::Mat checker(8, 8, CV_8UC3);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) checker.at<cv::Vec3b>(y, x) = cv::Vec3b::all((x + y) % 2 ? 200 : 0);
  EXPECT_EQ(Texture(checker).levels.back().at<cv::Vec3b>(0, 0), cv::Vec3b::all(100));
}

// An sRGB colour texture is filtered in linear light: a black and white checker's mean is half
// the light (0.5, stored as sRGB byte 188), not the mean of the encoded bytes (0.5 encoded, 0.214
// in light), and halfway between a black and a white texel reads 0.5 too.
TEST(Texture, SrgbTexturesAreFilteredAndMipMappedInLinearLight) {
  cv::Mat checker(8, 8, CV_8UC4);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      checker.at<cv::Vec4b>(y, x) = (x + y) % 2 ? cv::Vec4b(255, 255, 255, 255) : cv::Vec4b(0, 0, 0, 0);
  const Texture srgb(checker, {}, TextureEncoding::Srgb);
  EXPECT_EQ(srgb.levels.back().at<cv::Vec4b>(0, 0), cv::Vec4b(188, 188, 188, 128));  // alpha stays linear
  const vec4 whole = sampleTexture(srgb, {0.5f, 0.5f}, 1.0f);  // one pixel covers the texture
  EXPECT_NEAR(whole.r, 0.5f, 0.005f);
  EXPECT_NEAR(whole.a, 0.5f, 0.005f);
  const Texture linear(checker);  // the same bytes as data: their plain mean
  EXPECT_NEAR(sampleTexture(linear, {0.5f, 0.5f}, 1.0f).r, 0.5f, 0.005f);

  const Texture edge(row({0, 255}), wrapBoth(TextureWrap::ClampToEdge), TextureEncoding::Srgb);
  EXPECT_FLOAT_EQ(sampleTexture(edge, {0.5f, 0.5f}, 0.0f).r, 0.5f);  // halfway: half the light
  const Texture grey(row({128}), {}, TextureEncoding::Srgb);
  EXPECT_NEAR(sampleTexture(grey, {0.5f, 0.5f}, 0.0f).g, 0.2158f, 1e-4f);  // the byte decoded
}

TEST(Texture, BilinearBetweenTexelCentres) {
  const Texture t(row({0, 255}), wrapBoth(TextureWrap::ClampToEdge));
  EXPECT_FLOAT_EQ(sampleTexture(t, {0.25f, 0.5f}, 0.0f).r, 0.0f);  // centre of texel 0
  EXPECT_FLOAT_EQ(sampleTexture(t, {0.5f, 0.5f}, 0.0f).g, 0.5f);   // halfway between the centres
  EXPECT_FLOAT_EQ(sampleTexture(t, {0.625f, 0.5f}, 0.0f).b, 0.75f);
  EXPECT_FLOAT_EQ(sampleTexture(t, {0.5f, 0.5f}, 0.0f).a, 1.0f);  // no alpha channel: opaque
  TextureSampler nearest = wrapBoth(TextureWrap::ClampToEdge);
  nearest.magnify_linear = false;
  EXPECT_FLOAT_EQ(sampleTexture(Texture(row({0, 255}), nearest), {0.45f, 0.5f}, 0.0f).r, 0.0f);
}

TEST(Texture, WrapModes) {
  const cv::Mat ramp = row({0, 85, 170, 255});
  const vec2 outside{1.125f, 0.5f};  // centre of texel 0 of the next repetition
  EXPECT_FLOAT_EQ(sampleTexture(Texture(ramp, wrapBoth(TextureWrap::Repeat)), outside, 0.0f).r, 0.0f);
  // Mirrored: the next repetition runs backwards, so its first texel is texel 3.
  EXPECT_FLOAT_EQ(sampleTexture(Texture(ramp, wrapBoth(TextureWrap::MirroredRepeat)), outside, 0.0f).r, 1.0f);
  EXPECT_FLOAT_EQ(sampleTexture(Texture(ramp, wrapBoth(TextureWrap::ClampToEdge)), outside, 0.0f).r, 1.0f);
  EXPECT_FLOAT_EQ(sampleTexture(Texture(ramp, wrapBoth(TextureWrap::Repeat)), {-0.875f, 0.5f}, 0.0f).r, 0.0f);
  EXPECT_FLOAT_EQ(
      sampleTexture(Texture(ramp, wrapBoth(TextureWrap::MirroredRepeat)), {-0.125f, 0.5f}, 0.0f).r, 0.0f);
}

// A one-texel checkerboard seen by a pixel that covers the whole texture reads its mean, not
// whichever texel the pixel centre hits (the aliasing mip levels exist to prevent).
TEST(Texture, FootprintChoosesTheMipLevel) {
  cv::Mat checker(64, 64, CV_8UC3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) checker.at<cv::Vec3b>(y, x) = cv::Vec3b::all((x + y) % 2 ? 255 : 0);
  const Texture t(checker);
  const vec2 uv{0.5f / 64.0f, 0.5f / 64.0f};  // centre of a black texel
  EXPECT_FLOAT_EQ(sampleTexture(t, uv, 0.0f).r, 0.0f);
  EXPECT_FLOAT_EQ(sampleTexture(t, uv, 1.0f / 64.0f).r, 0.0f);  // one texel per pixel: level 0
  EXPECT_NEAR(sampleTexture(t, uv, 1.0f).r, 0.5f, 0.003f);      // whole texture: 1x1 level
  EXPECT_NEAR(sampleTexture(t, uv, 8.0f).r, 0.5f, 0.003f);      // beyond the chain: its top
  const float mid = sampleTexture(t, uv, 2.0f / 64.0f).r;       // level 1: 2x2 blocks averaged
  EXPECT_NEAR(mid, 0.5f, 0.003f);
  TextureSampler no_mips;
  no_mips.use_mips = false;
  EXPECT_FLOAT_EQ(sampleTexture(Texture(checker, no_mips), uv, 1.0f).r, 0.0f);
}

TEST(Texture, EmptyAndNonFiniteInputs) {
  EXPECT_EQ(sampleTexture(Texture{}, {0.3f, 0.3f}, 0.0f), vec4(1.0f));
  const Texture t(row({0, 255}));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const vec4 v = sampleTexture(t, {nan, 0.5f}, nan);
  EXPECT_TRUE(std::isfinite(v.r) && std::isfinite(v.a));
  const vec4 far = sampleTexture(t, {1e30f, -1e30f}, std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isfinite(far.r));
}

}  // namespace
}  // namespace holo
