// Every glTF texture map in both renderers, through `render`'s method factory: the path tracer
// ("gt") and the live renderer ("ours"), on quads whose answer is worked out here from the glTF
// specification (ray-plane geometry, the sRGB curve, KHR_texture_transform's matrix), not from
// the renderers' code: a normal map moves the mirror reflection as its tilt predicts, occlusion
// 0 leaves only the emission, an emissive texture shows texel x strength, the transmission
// texture chooses where light passes, the clearcoat follows its weight texture and its own normal
// map, the layer textures scale their factors, MASK and BLEND show
// what is behind, texCoord 1 with a transform lands the texel computed, a minified checker
// averages to its mean instead of aliasing, degenerate uvs stay finite, and the Khronos sample
// relics render finite. Beside them, KHR_materials_ior and KHR_materials_specular's colour (and
// its texture) set an opaque dielectric's reflection as the extensions' F0 predicts.
#include <gtest/gtest.h>

#include <cmath>

#include "holo/core/equirect.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/image.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "holo/reflect/view.hpp"
#include "shared_data.hpp"

namespace holo::eval {
namespace {

constexpr int kView = 16;

// The sRGB decoding curve (IEC 61966-2-1), written out here rather than taken from core.
float srgbDecoded(int byte) {
  const double c = byte / 255.0;
  return float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

// A unit quad in the plane z = depth facing +Z (x, y in [-half, half]), TEXCOORD_0 = (x + 0.5,
// 0.5 - y) (glTF's v points down) scaled to the quad, material 0.
TriangleMesh quad(float depth, float half = 0.5f, int material = 0) {
  TriangleMesh m;
  m.positions = {{-half, -half, depth}, {half, -half, depth}, {half, half, depth}, {-half, half, depth}};
  m.normals.assign(4, vec3(0.0f, 0.0f, 1.0f));
  for (const vec3& p : m.positions) m.uvs.push_back({(p.x + half) / (2 * half), (half - p.y) / (2 * half)});
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.material = material;
  return m;
}

// The quad at depth 0 with one material and its textures.
Model quadRelic(const Material& material, std::vector<Texture> textures = {}) {
  Model relic;
  relic.meshes = {quad(0.0f)};
  relic.materials = {material};
  relic.textures = std::move(textures);
  return relic;
}

// A BGRA image from RGBA texels listed row by row: sRGB colour (the colour slots) or linear data.
Texture texture(int w, int h, const std::vector<cv::Vec4b>& rgba, bool nearest,
                TextureEncoding encoding = TextureEncoding::Srgb) {
  cv::Mat image(h, w, CV_8UC4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const cv::Vec4b c = rgba[std::size_t(y * w + x)];
      image.at<cv::Vec4b>(y, x) = cv::Vec4b(c[2], c[1], c[0], c[3]);
    }
  TextureSampler sampler;
  sampler.magnify_linear = sampler.minify_linear = !nearest;
  return Texture(image, sampler, encoding);
}

Material black() {
  Material m;
  m.base_colour = vec3(0.0f);
  m.roughness = 1.0f;
  m.specular = 0.0f;
  return m;
}

cv::Mat panorama(const std::function<vec3(const vec3&)>& radiance, int w = 512, int h = 256) {
  cv::Mat pano(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      setRgb(pano, x, y, radiance(equirect::uvToDirection({(x + 0.5f) / w, (y + 0.5f) / h})));
  return pano;
}

ReflectionScene sceneOf(Model relic, const cv::Mat& pano) {
  ReflectionScene s;
  s.scene_name = s.relic_name = "texture test";
  s.relic = std::move(relic);
  s.panorama = pano;
  return s;
}

// Eye on +Z looking at the origin; the quad of half-size 0.5 at z = 0 fills the view.
CameraModel frontCamera(int size = kView) {
  const float eye = 2.0f;
  const float fov = 2.0f * std::atan(0.5f / eye) * 180.0f / kPi;
  return reflect::lookAtCamera(vec3(0.0f, 0.0f, eye), vec3(0.0f), fov, size, size);
}

// Where the pixel centre's ray meets the plane z = depth (x, y).
vec2 planePoint(const CameraModel& camera, int x, int y, float depth = 0.0f) {
  const Ray ray = reflect::primaryRay(camera, vec2(float(x), float(y)));
  const float t = (depth - ray.origin.z) / ray.direction.z;
  const vec3 p = ray.origin + t * ray.direction;
  return {p.x, p.y};
}

MethodSettings settings(int spp) {
  MethodSettings s;
  s.spp = spp;
  s.with_visitors = false;
  s.ibl_levels = 6;
  return s;
}

cv::Mat render(const std::string& method, const ReflectionScene& scene, const CameraModel& camera,
               int spp = 16) {
  return renderMethod(method, scene, camera, settings(spp)).image;
}

const std::vector<std::string> kRenderers = {"gt", "ours"};

TEST(TextureMaps, EmissiveTextureTimesStrengthInBothRenderers) {
  // 4x4 texels of distinct colours, nearest filtering; emissive strength 3; black world.
  std::vector<cv::Vec4b> texels;
  for (int i = 0; i < 16; ++i)
    texels.emplace_back(uchar(16 * i + 8), uchar(255 - 12 * i), uchar(40 + 9 * i), 255);
  Material m = black();
  m.emission = vec3(3.0f);
  m.emissive_texture.index = 0;
  Model relic = quadRelic(m, {texture(4, 4, texels, true)});
  const ReflectionScene scene = sceneOf(relic, cv::Mat(8, 16, CV_32FC3, cv::Scalar::all(0)));
  const CameraModel camera = frontCamera();
  for (const std::string& method : kRenderers) {
    const cv::Mat image = render(method, scene, camera);
    for (int y = 1; y < kView; y += 4)  // pixel centres well inside a texel
      for (int x = 1; x < kView; x += 4) {
        const vec2 p = planePoint(camera, x, y);
        const int tx = int((p.x + 0.5f) * 4.0f), ty = int((0.5f - p.y) * 4.0f);
        const cv::Vec4b t = texels[std::size_t(ty * 4 + tx)];
        const vec3 expected = 3.0f * vec3(srgbDecoded(t[0]), srgbDecoded(t[1]), srgbDecoded(t[2]));
        const vec3 got = rgbAt(image, x, y);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(got[c], expected[c], 0.01f * expected[c] + 1e-3f)
              << method << " pixel " << x << "," << y;
      }
  }
}

TEST(TextureMaps, OcclusionZeroKillsTheLightButNotTheEmission) {
  // A white Lambert quad under a white sky: occlusion texture R = 0 at full strength leaves its
  // emission (0.25) alone; at strength 0 the reflected sky adds to it.
  Material m;
  m.base_colour = vec3(1.0f);
  m.roughness = 1.0f;
  m.emission = vec3(0.25f);
  m.occlusion_texture.index = 0;
  Model relic = quadRelic(m, {texture(1, 1, {cv::Vec4b(0, 0, 0, 255)}, false, TextureEncoding::Linear)});
  const cv::Mat white(8, 16, CV_32FC3, cv::Scalar::all(1.0));
  const CameraModel camera = frontCamera();
  for (const std::string& method : kRenderers) {
    const cv::Mat occluded = render(method, sceneOf(relic, white), camera);
    Model unoccluded = relic;
    unoccluded.materials[0].occlusion_strength = 0.0f;
    const cv::Mat lit = render(method, sceneOf(unoccluded, white), camera);
    for (int y = 2; y < kView; y += 5)
      for (int x = 2; x < kView; x += 5) {
        EXPECT_NEAR(rgbAt(occluded, x, y).g, 0.25f, 1e-3f) << method;
        EXPECT_GT(rgbAt(lit, x, y).g, 0.25f + 0.3f) << method;
      }
  }
}

TEST(TextureMaps, ANormalMapMovesTheMirrorReflectionAsItsTiltPredicts) {
  // A mirror quad whose normal map tilts every normal by 20 degrees towards +U (+X here); the
  // sky's radiance is 1 + 0.9 x, so the reflected ray r of the view ray d about the tilted normal
  // n = (sin 20, 0, cos 20) reads 1 + 0.9 r.x.
  const float tilt = 20.0f * kPi / 180.0f;
  const auto encode = [](float v) { return uchar(std::lround((v + 1.0f) * 0.5f * 255.0f)); };
  Material m;
  m.base_colour = vec3(1.0f);
  m.metallic = 1.0f;
  m.roughness = 0.0f;
  m.normal_texture.index = 0;
  Model relic = quadRelic(
      m, {texture(1, 1, {cv::Vec4b(encode(std::sin(tilt)), encode(0.0f), encode(std::cos(tilt)), 255)}, false,
                  TextureEncoding::Linear)});
  const cv::Mat sky = panorama([](const vec3& d) { return vec3(1.0f + 0.9f * d.x); });
  const CameraModel camera = frontCamera();
  const vec3 n(std::sin(tilt), 0.0f, std::cos(tilt));
  for (const std::string& method : kRenderers) {
    const cv::Mat image = render(method, sceneOf(relic, sky), camera, 64);
    for (int y = 3; y < kView; y += 5)
      for (int x = 3; x < kView; x += 5) {
        const vec3 d = reflect::primaryRay(camera, vec2(float(x), float(y))).direction;
        const vec3 r = d - 2.0f * glm::dot(d, n) * n;
        const float predicted = 1.0f + 0.9f * r.x;
        const float unmapped = 1.0f + 0.9f * d.x;  // the flat mirror's reflection, r.x = d.x
        ASSERT_GT(std::abs(predicted - unmapped), 0.5f);
        EXPECT_NEAR(rgbAt(image, x, y).g, predicted, 0.03f * predicted)
            << method << " pixel " << x << "," << y;
      }
  }
}

// A 2x1 linear texture, nearest filtering: the quad's left half reads `left`, its right half `right`.
Texture halves(const cv::Vec4b& left, const cv::Vec4b& right) {
  return texture(2, 1, {left, right}, true, TextureEncoding::Linear);
}

TEST(TextureMaps, TheTransmissionTextureChoosesWhereLightPassesInBothRenderers) {
  // A thin-walled white quad of IOR 1 without specular reflection, transmission 1 times the
  // texture's R: 0 on the left (an opaque white Lambert lit by the sky in front of it, 0.1), 1 on
  // the right (the hall behind it, 1.0, seen straight through).
  Material m;
  m.base_colour = vec3(1.0f);
  m.roughness = 0.0f;
  m.specular = 0.0f;
  m.ior = 1.0f;
  m.transmission = 1.0f;
  m.transmission_texture.index = 0;
  Model relic = quadRelic(m, {halves(cv::Vec4b(0, 0, 0, 255), cv::Vec4b(255, 0, 0, 255))});
  const cv::Mat sky = panorama([](const vec3& d) { return vec3(d.z < 0.0f ? 1.0f : 0.1f); });
  const CameraModel camera = frontCamera();
  for (const std::string& method : kRenderers) {
    const cv::Mat image = render(method, sceneOf(relic, sky), camera, 64);
    for (int y = 1; y < kView; y += 3)
      for (int x = 1; x < kView; x += 3) {
        const vec2 p = planePoint(camera, x, y);
        if (std::abs(p.x) < 0.05f) continue;  // the texel border
        EXPECT_NEAR(rgbAt(image, x, y).g, p.x < 0.0f ? 0.1f : 1.0f, p.x < 0.0f ? 0.015f : 0.03f)
            << method << " pixel " << x << "," << y;
      }
  }
}

TEST(TextureMaps, TheClearcoatFollowsItsTexturesAndItsOwnNormalMapInBothRenderers) {
  // A black base (no diffuse, no specular) under a smooth clearcoat whose weight is the
  // texture's R (0 left, 1 right) and whose own normal map tilts it by 20 degrees towards +X; the
  // base's normal is not mapped. The sky's radiance is 1 + 0.9 x: the coat reflects F(n.v) of
  // what the mirror ray r about the tilted normal n reads, 1 + 0.9 r.x (F: Schlick's of IOR 1.5,
  // which the split sum and the exact Fresnel meet within 1% here).
  const float tilt = 20.0f * kPi / 180.0f;
  const auto encode = [](float v) { return uchar(std::lround((v + 1.0f) * 0.5f * 255.0f)); };
  Material m = black();
  m.clearcoat = 1.0f;
  m.clearcoat_roughness = 0.0f;
  m.clearcoat_texture.index = 0;
  m.clearcoat_normal_texture.index = 1;
  Model relic = quadRelic(
      m, {halves(cv::Vec4b(0, 0, 0, 255), cv::Vec4b(255, 0, 0, 255)),
          texture(1, 1, {cv::Vec4b(encode(std::sin(tilt)), encode(0.0f), encode(std::cos(tilt)), 255)}, false,
                  TextureEncoding::Linear)});
  const cv::Mat sky = panorama([](const vec3& d) { return vec3(1.0f + 0.9f * d.x); });
  const CameraModel camera = frontCamera();
  const vec3 n(std::sin(tilt), 0.0f, std::cos(tilt));
  for (const std::string& method : kRenderers) {
    const cv::Mat image = render(method, sceneOf(relic, sky), camera, 1024);
    for (int y = 1; y < kView; y += 3)
      for (int x = 1; x < kView; x += 3) {
        const vec2 p = planePoint(camera, x, y);
        if (std::abs(p.x) < 0.05f) continue;  // the texel border
        const float got = rgbAt(image, x, y).g;
        if (p.x < 0.0f) {
          EXPECT_NEAR(got, 0.0f, 1e-3f) << method << " pixel " << x << "," << y;
          continue;
        }
        const vec3 d = reflect::primaryRay(camera, vec2(float(x), float(y))).direction;
        const vec3 r = d - 2.0f * glm::dot(d, n) * n;
        const float fresnel = 0.04f + 0.96f * std::pow(1.0f - glm::dot(n, -d), 5.0f);
        const float predicted = fresnel * (1.0f + 0.9f * r.x);
        const float unmapped = fresnel * (1.0f + 0.9f * d.x);  // the coat along the base's normal
        ASSERT_GT(std::abs(predicted - unmapped), 0.25f * predicted);
        EXPECT_NEAR(got, predicted, 0.06f * predicted) << method << " pixel " << x << "," << y;
      }
  }
}

TEST(TextureMaps, TextureChannelsScaleTheLayerFactorsAtTheHitPoint) {
  // Factors times channels, per texel (left, right): transmission R (0.2, 1), thickness G
  // (0: thin-walled; 1: a volume), clearcoat R and clearcoat roughness G.
  Material m;
  m.transmission = 0.8f;
  m.thickness = 0.05f;
  m.clearcoat = 0.5f;
  m.clearcoat_roughness = 0.6f;
  m.transmission_texture.index = m.thickness_texture.index = m.clearcoat_texture.index =
      m.clearcoat_roughness_texture.index = 0;
  Model relic = quadRelic(m, {halves(cv::Vec4b(51, 0, 0, 255), cv::Vec4b(255, 255, 0, 255))});
  reflect::RenderScene render_scene(relic, {});
  const RayScene& traced = render_scene.relicOnly();
  const CameraModel camera = frontCamera();
  for (const int x : {3, kView - 4}) {
    const Ray ray = reflect::primaryRay(camera, vec2(float(x), float(kView / 2)));
    const RayHit hit = traced.intersect(ray);
    ASSERT_TRUE(hit.hit());
    const reflect::SurfacePoint s = reflect::resolveSurface(render_scene, traced, ray, hit, 0.0f);
    const bool left = x < kView / 2;
    EXPECT_NEAR(s.material.transmission, 0.8f * (left ? 0.2f : 1.0f), 1e-3f) << x;
    EXPECT_EQ(s.material.thin_walled, left) << x;
    EXPECT_NEAR(s.material.clearcoat, 0.5f * (left ? 0.2f : 1.0f), 1e-3f) << x;
    EXPECT_NEAR(s.material.clearcoat_roughness, left ? 0.0f : 0.6f, 1e-3f) << x;
    EXPECT_NEAR(glm::dot(s.clearcoat_normal, s.normal), 1.0f, 1e-6f) << "no coat normal map: the base's";
  }
}

// A front quad (red emission, texture `front_alpha`) over a larger green-emitting quad behind.
Model frontOverBack(AlphaMode mode, const std::vector<cv::Vec4b>& front_texels, int side) {
  Model relic;
  relic.meshes = {quad(0.0f), quad(-0.5f, 1.0f, 1)};
  Material front = black();
  front.emission = vec3(1.0f, 0.0f, 0.0f);
  front.alpha_mode = mode;
  front.base_colour_texture.index = 0;
  Material back = black();
  back.emission = vec3(0.0f, 1.0f, 0.0f);
  relic.materials = {front, back};
  relic.textures = {texture(side, side, front_texels, true)};
  return relic;
}

TEST(TextureMaps, AlphaMaskShowsWhatIsBehindThroughCutTexels) {
  // A 2x2 checker of opaque and cut texels (alpha 255 / 0, cutoff 0.5).
  const cv::Vec4b solid(255, 255, 255, 255), cut(255, 255, 255, 0);
  const ReflectionScene scene = sceneOf(frontOverBack(AlphaMode::Mask, {solid, cut, cut, solid}, 2),
                                        cv::Mat(8, 16, CV_32FC3, cv::Scalar::all(0)));
  const CameraModel camera = frontCamera();
  for (const std::string& method : kRenderers) {
    const cv::Mat image = render(method, scene, camera);
    for (int y = 1; y < kView; y += 3)
      for (int x = 1; x < kView; x += 3) {
        const vec2 p = planePoint(camera, x, y);
        if (std::abs(p.x) < 0.05f || std::abs(p.y) < 0.05f) continue;  // texel borders
        const bool opaque = (p.x < 0.0f) == (p.y > 0.0f);  // texels (0,0) and (1,1): top left, bottom right
        const vec3 got = rgbAt(image, x, y);
        EXPECT_NEAR(got.r, opaque ? 1.0f : 0.0f, 1e-3f) << method << " pixel " << x << "," << y;
        EXPECT_NEAR(got.g, opaque ? 0.0f : 1.0f, 1e-3f) << method << " pixel " << x << "," << y;
      }
  }
}

TEST(TextureMaps, AlphaBlendCompositesOverWhatIsBehind) {
  // alpha 0.25 everywhere: a quarter of the red front over three quarters of the green back.
  const ReflectionScene scene = sceneOf(frontOverBack(AlphaMode::Blend, {cv::Vec4b(255, 255, 255, 64)}, 1),
                                        cv::Mat(8, 16, CV_32FC3, cv::Scalar::all(0)));
  const float alpha = 64.0f / 255.0f;
  const CameraModel camera = frontCamera(8);
  for (const std::string& method : kRenderers) {
    const cv::Mat image = render(method, scene, camera, 256);
    cv::Scalar mean = cv::mean(image);  // BGR
    EXPECT_NEAR(mean[2], alpha, 0.02) << method;
    EXPECT_NEAR(mean[1], 1.0 - alpha, 0.02) << method;
  }
}

TEST(TextureMaps, TexCoord1AndATextureTransformLandTheTexelComputed) {
  // TEXCOORD_0 is constant (it would read one texel everywhere); TEXCOORD_1 = (y + 0.5, x + 0.5)
  // (axes swapped), then scale 0.5, rotation 90 degrees and offset (0.25, 0.5) per
  // KHR_texture_transform: uv' = offset + R (scale uv) with R = [cos sin; -sin cos] (glTF's uv
  // space has v down: KhronosGroup/glTF#1563, what Babylon, Blender and three.js do).
  std::vector<cv::Vec4b> texels;
  for (int i = 0; i < 16; ++i)
    texels.emplace_back(uchar(15 * i + 10), uchar(250 - 15 * i), uchar(i % 2 ? 220 : 30), 255);
  Model relic;
  TriangleMesh mesh = quad(0.0f);
  mesh.uvs.assign(4, vec2(0.9f, 0.9f));
  for (const vec3& p : mesh.positions) mesh.uvs1.push_back({p.y + 0.5f, p.x + 0.5f});
  relic.meshes = {mesh};
  Material m = black();
  m.emission = vec3(1.0f);
  m.emissive_texture.index = 0;
  m.emissive_texture.tex_coord = 1;
  m.emissive_texture.scale = vec2(0.5f);
  m.emissive_texture.rotation = 0.5f * kPi;
  m.emissive_texture.offset = vec2(0.25f, 0.5f);
  relic.materials = {m};
  relic.textures = {texture(4, 4, texels, true)};
  const ReflectionScene scene = sceneOf(relic, cv::Mat(8, 16, CV_32FC3, cv::Scalar::all(0)));
  const CameraModel camera = frontCamera();
  for (const std::string& method : kRenderers) {
    const cv::Mat image = render(method, scene, camera);
    int checked = 0;
    for (int y = 0; y < kView; ++y)
      for (int x = 0; x < kView; ++x) {
        const vec2 p = planePoint(camera, x, y);
        const vec2 uv1(0.5f * (p.y + 0.5f), 0.5f * (p.x + 0.5f));  // scaled
        const vec2 uv(0.25f + uv1.y, 0.5f - uv1.x);                // rotated by 90 degrees, offset
        const float fx = uv.x * 4.0f, fy = uv.y * 4.0f;
        if (std::abs(fx - std::round(fx)) < 0.1f || std::abs(fy - std::round(fy)) < 0.1f) continue;
        const int tx = ((int(std::floor(fx)) % 4) + 4) % 4, ty = ((int(std::floor(fy)) % 4) + 4) % 4;
        const cv::Vec4b t = texels[std::size_t(ty * 4 + tx)];
        const vec3 got = rgbAt(image, x, y);
        EXPECT_NEAR(got.r, srgbDecoded(t[0]), 0.01f) << method << " pixel " << x << "," << y;
        EXPECT_NEAR(got.b, srgbDecoded(t[2]), 0.01f) << method << " pixel " << x << "," << y;
        ++checked;
      }
    EXPECT_GT(checked, 100);
  }
}

// The variance over the view of a quad textured with a one-texel 256^2 black and white checker
// (emissive, so the image is the texture itself), seen by a 13^2 view: about 20 texels per pixel
// (not a whole number, so pixel centres do not all land on texels of one colour).
struct CheckerStats {
  double mean = 0, variance = 0;
};
CheckerStats checkerStats(const cv::Mat& image) {
  cv::Scalar mean, stddev;
  std::vector<cv::Mat> channels;
  cv::split(image, channels);
  cv::meanStdDev(channels[1], mean, stddev);
  return {mean[0], stddev[0] * stddev[0]};
}

TEST(TextureMaps, AMinifiedCheckerAveragesToItsMeanInsteadOfAliasing) {
  constexpr int kSide = 256;
  std::vector<cv::Vec4b> texels;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const uchar v = (x + y) % 2 ? 255 : 0;
      texels.emplace_back(v, v, v, 255);
    }
  Material m = black();
  m.emission = vec3(1.0f);
  m.emissive_texture.index = 0;
  Model relic = quadRelic(m, {texture(kSide, kSide, texels, false)});
  const ReflectionScene scene = sceneOf(relic, cv::Mat(8, 16, CV_32FC3, cv::Scalar::all(0)));
  constexpr int kSmall = 13;
  const CameraModel camera = frontCamera(kSmall);
  // The mip chain averages the light of the sRGB texels: half of white (docs/materials.md).
  const double mip_mean = 0.5;
  double filtered_variance = 0.0;
  for (const std::string& method : kRenderers) {
    const CheckerStats filtered = checkerStats(render(method, scene, camera, 4));
    EXPECT_NEAR(filtered.mean, mip_mean, 0.03) << method;
    EXPECT_LT(filtered.variance, 0.002) << method;
    filtered_variance = std::max(filtered_variance, filtered.variance);
  }
  // Without the footprint (level 0 at every pixel centre), the same view aliases.
  reflect::RenderScene render_scene(scene.relic, {});
  const RayScene& traced = render_scene.relicOnly();
  cv::Mat unfiltered(kSmall, kSmall, CV_32FC3, cv::Scalar::all(0));
  for (int y = 0; y < kSmall; ++y)
    for (int x = 0; x < kSmall; ++x) {
      const Ray ray = reflect::primaryRay(camera, vec2(float(x), float(y)));
      const RayHit hit = traced.intersect(ray);
      ASSERT_TRUE(hit.hit());
      setRgb(unfiltered, x, y, reflect::resolveSurface(render_scene, traced, ray, hit, 0.0f).emission);
    }
  const CheckerStats aliased = checkerStats(unfiltered);
  EXPECT_GT(aliased.variance, 0.01);
  EXPECT_GT(aliased.variance, 10.0 * filtered_variance);
}

TEST(TextureMaps, SingleSidedBackFacesAreCulledDoubleSidedOnesShadedWithTheReversedNormal) {
  // The quad seen from behind (eye on -Z), a green-emitting quad further back. Single-sided: the
  // front quad is culled and the green one shows. Double-sided: the front quad hides it and,
  // white Lambert under a sky that is 1 towards -Z and 0 towards +Z, reads the sky on its back's
  // side (reversed normal -Z), not black.
  Model relic;
  relic.meshes = {quad(0.0f), quad(0.5f, 1.0f, 1)};
  relic.meshes[1].normals.assign(4, vec3(0.0f, 0.0f, -1.0f));
  std::swap(relic.meshes[1].triangles[0].y, relic.meshes[1].triangles[0].z);  // faces -Z
  std::swap(relic.meshes[1].triangles[1].y, relic.meshes[1].triangles[1].z);
  Material white;
  white.base_colour = vec3(1.0f);
  white.roughness = 1.0f;
  Material green = black();
  green.emission = vec3(0.0f, 1.0f, 0.0f);
  relic.materials = {white, green};
  const cv::Mat sky = panorama([](const vec3& d) { return vec3(d.z < 0.0f ? 1.0f : 0.0f); });
  const CameraModel camera = reflect::lookAtCamera(vec3(0.0f, 0.0f, -2.0f), vec3(0.0f),
                                                   2.0f * std::atan(0.4f / 2.0f) * 180.0f / kPi, 8, 8);
  for (const std::string& method : kRenderers) {
    const vec3 culled = rgbAt(render(method, sceneOf(relic, sky), camera), 4, 4);
    EXPECT_NEAR(culled.g, 1.0f, 1e-3f) << method;
    EXPECT_NEAR(culled.r, 0.0f, 1e-3f) << method;
    Model two_sided = relic;
    two_sided.materials[0].double_sided = true;
    const vec3 shaded = rgbAt(render(method, sceneOf(two_sided, sky), camera, 64), 4, 4);
    EXPECT_GT(shaded.r, 0.5f) << method;               // the lit hemisphere is the reversed normal's
    EXPECT_NEAR(shaded.r, shaded.g, 0.05f) << method;  // white, not the green behind
  }
}

TEST(TextureMaps, DegenerateUvsGiveFiniteOutput) {
  // Every uv the same: zero-area tangent frames under a normal map that tilts hard.
  Model relic;
  TriangleMesh mesh = quad(0.0f);
  mesh.uvs.assign(4, vec2(0.3f, 0.3f));
  relic.meshes = {mesh};
  Material m;
  m.normal_texture.index = 0;
  m.normal_scale = 5.0f;
  m.occlusion_texture.index = 0;
  relic.materials = {m};
  relic.textures = {texture(1, 1, {cv::Vec4b(255, 0, 10, 255)}, false, TextureEncoding::Linear)};
  const ReflectionScene scene = sceneOf(relic, cv::Mat(8, 16, CV_32FC3, cv::Scalar::all(1.0)));
  for (const std::string& method : kRenderers) {
    const cv::Mat image = render(method, scene, frontCamera(8));
    EXPECT_TRUE(cv::checkRange(image)) << method;
    EXPECT_GT(cv::mean(image)[1], 0.0) << method;
  }
}

// KHR_materials_ior and KHR_materials_specular on an opaque dielectric: a smooth quad with a
// black base (nothing but the dielectric's reflection) under a uniform white sky, seen nearly
// head-on, reflects Schlick's F = F0 + (specular - F0)(1 - cos)^5 of the view ray, F0 = min(((n -
// 1) / (n + 1))^2 specular colour, 1) specular (the extension's fresnel_mix, written out here).
float specularF0(double ior, double colour) {
  const double r = (ior - 1.0) / (ior + 1.0);
  return float(std::min(r * r * colour, 1.0));
}

Model smoothDielectric(float ior, const vec3& specular_colour, const vec3& base = vec3(0.0f)) {
  Material m;
  m.base_colour = base;
  m.roughness = 0.0f;
  m.ior = ior;
  m.specular_colour = specular_colour;
  Model relic = quadRelic(m);
  return relic;
}

const cv::Mat& whiteSky() {
  static const cv::Mat white(8, 16, CV_32FC3, cv::Scalar::all(1.0));
  return white;
}

// Schlick's F of the view ray through pixel (x, y) on the quad (normal +Z) for F0 `f0`.
float schlickAt(const CameraModel& camera, int x, int y, float f0) {
  const float c = -reflect::primaryRay(camera, vec2(float(x), float(y))).direction.z;
  return f0 + (1.0f - f0) * std::pow(1.0f - c, 5.0f);
}

TEST(SpecularAndIor, TheIorSetsTheOpaqueDielectricsReflectionInBothRenderers) {
  const float f0_2 = specularF0(2.0, 1.0), f0_15 = specularF0(1.5, 1.0);
  ASSERT_NEAR(f0_2, 1.0f / 9.0f, 1e-6f);
  ASSERT_NEAR(f0_15, 0.04f, 1e-6f);
  const CameraModel camera = frontCamera();
  for (const std::string& method : kRenderers) {
    const cv::Mat ior2 = render(method, sceneOf(smoothDielectric(2.0f, vec3(1.0f)), whiteSky()), camera);
    const cv::Mat ior15 = render(method, sceneOf(smoothDielectric(1.5f, vec3(1.0f)), whiteSky()), camera);
    for (int y = 1; y < kView; y += 3)
      for (int x = 1; x < kView; x += 3) {
        const float expected2 = schlickAt(camera, x, y, f0_2), expected15 = schlickAt(camera, x, y, f0_15);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(rgbAt(ior2, x, y)[c], expected2, 0.02f * expected2)
              << method << " pixel " << x << "," << y;
          EXPECT_NEAR(rgbAt(ior15, x, y)[c], expected15, 0.02f * expected15)
              << method << " pixel " << x << "," << y;
        }
      }
  }
}

TEST(SpecularAndIor, TheSpecularColourAndItsTextureTintTheReflectionInBothRenderers) {
  // IOR 2 under a red specular colour: red only. Colour 1 times a texture whose left texel is
  // sRGB red (255, 0, 0) and right texel sRGB green (0, 128, 0): red F0 on the left, green F0 x
  // the decoded 128 (0.216, not the byte's 0.502) on the right.
  const float f0 = specularF0(2.0, 1.0);
  const CameraModel camera = frontCamera();
  Model textured = smoothDielectric(2.0f, vec3(1.0f));
  textured.materials[0].specular_colour_texture.index = 0;
  textured.textures = {texture(2, 1, {cv::Vec4b(255, 0, 0, 255), cv::Vec4b(0, 128, 0, 255)}, true)};
  const float green = srgbDecoded(128);
  for (const std::string& method : kRenderers) {
    const cv::Mat red =
        render(method, sceneOf(smoothDielectric(2.0f, vec3(1.0f, 0.0f, 0.0f)), whiteSky()), camera);
    const cv::Mat split = render(method, sceneOf(textured, whiteSky()), camera);
    for (int y = 1; y < kView; y += 3)
      for (int x = 1; x < kView; x += 3) {
        const float f = schlickAt(camera, x, y, f0);
        const vec3 tinted = rgbAt(red, x, y);
        EXPECT_NEAR(tinted.r, f, 0.02f * f) << method << " pixel " << x << "," << y;
        EXPECT_LT(tinted.g, 1e-3f) << method << " pixel " << x << "," << y;
        EXPECT_LT(tinted.b, 1e-3f) << method << " pixel " << x << "," << y;
        const vec2 p = planePoint(camera, x, y);
        if (std::abs(p.x) < 0.05f) continue;  // the texel border
        const vec3 got = rgbAt(split, x, y);
        const float expected_r = p.x < 0.0f ? f : schlickAt(camera, x, y, 0.0f);
        const float expected_g =
            p.x < 0.0f ? schlickAt(camera, x, y, 0.0f) : schlickAt(camera, x, y, f0 * green);
        EXPECT_NEAR(got.r, expected_r, 0.02f * expected_r + 1e-3f) << method << " pixel " << x << "," << y;
        EXPECT_NEAR(got.g, expected_g, 0.02f * expected_g + 1e-3f) << method << " pixel " << x << "," << y;
        EXPECT_LT(got.b, 1e-3f) << method << " pixel " << x << "," << y;
      }
  }
}

TEST(SpecularAndIor, IorOneReflectsNothingHeadOnInBothRenderers) {
  // F0 0: only Schlick's grazing rise is left, below 1e-7 at the view's steepest 14 degrees.
  const CameraModel camera = frontCamera();
  for (const std::string& method : kRenderers) {
    const cv::Mat image = render(method, sceneOf(smoothDielectric(1.0f, vec3(1.0f)), whiteSky()), camera);
    for (int y = 1; y < kView; y += 3)
      for (int x = 1; x < kView; x += 3) {
        ASSERT_LT(schlickAt(camera, x, y, 0.0f), 1e-7f);
        EXPECT_LT(rgbAt(image, x, y).g, 1e-3f) << method << " pixel " << x << "," << y;
      }
  }
}

TEST(SpecularAndIor, AHugeIorOrSpecularColourClampsF0ToOneAndStaysFinite) {
  // IOR 1e30 on a black base, or colour (10, 10, 10) at IOR 2 (10 / 9): F0 1, a white mirror. Over a
  // white Lambert base, a red colour of 50 at IOR 2 (F0 red 1) leaves nothing to the diffuse:
  // red mirror, no green (fresnel_mix's 1 - max over RGB of F).
  const CameraModel camera = frontCamera(8);
  const std::vector<std::pair<Model, vec3>> cases = {
      {smoothDielectric(1e30f, vec3(1.0f)), vec3(1.0f)},
      {smoothDielectric(2.0f, vec3(10.0f)), vec3(1.0f)},
      {smoothDielectric(2.0f, vec3(50.0f, 0.0f, 0.0f), vec3(1.0f)), vec3(1.0f, 0.0f, 0.0f)}};
  for (const std::string& method : kRenderers)
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const cv::Mat image = render(method, sceneOf(cases[i].first, whiteSky()), camera);
      EXPECT_TRUE(cv::checkRange(image)) << method << " case " << i;
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(rgbAt(image, x, y)[c], cases[i].second[c], 0.02f)
                << method << " case " << i << " pixel " << x << "," << y << " channel " << c;
    }
}

class KhronosRelics : public ::testing::TestWithParam<std::string> {};

TEST_P(KhronosRelics, RenderFiniteInBothRenderers) {
  const std::string file = "models/" + GetParam();
  HOLO_REQUIRE_SHARED_DATA(file);
  SceneOptions options;
  options.relic = test::sharedData(file).string();
  options.fit = true;
  const ReflectionScene scene = loadReflectionScene(options);
  ViewOptions view;
  view.width = view.height = 24;
  const CameraModel camera = viewCamera(view, scene);
  for (const std::string& method : kRenderers) {
    const cv::Mat image = render(method, scene, camera, 4);
    EXPECT_TRUE(cv::checkRange(image)) << method;
    EXPECT_GT(cv::norm(image, cv::NORM_L1), 0.0) << method << ": the relic is not in the view";
  }
}

// The Khronos files with normal, occlusion or emissive maps (and their tangent-less meshes).
INSTANTIATE_TEST_SUITE_P(Files, KhronosRelics,
                         ::testing::Values("khronos_glass_hurricane_candle_holder.glb",
                                           "khronos_clearcoat_wicker.glb", "khronos_attenuation_test.glb",
                                           "khronos_transmission_roughness_test.glb"));

}  // namespace
}  // namespace holo::eval
