#include "holo/sim/sensor_noise.hpp"

#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::sim {

namespace {

std::uint64_t splitmix(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

PixelRng::PixelRng(std::uint64_t seed, std::uint64_t stream, int x, int y) {
  std::uint64_t h = seed;
  h = splitmix(h) ^ stream;
  h = splitmix(h) ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(x));
  h = splitmix(h) ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(y)) << 32);
  state_ = splitmix(h);
}

std::uint64_t PixelRng::next() {
  return splitmix(state_);
}

float PixelRng::uniform() {
  return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f);
}

float PixelRng::normal() {
  const float u1 = 1.0f - uniform();  // (0, 1]: log stays finite
  const float u2 = uniform();
  return std::sqrt(-2.0f * std::log(u1)) * std::cos(2.0f * kPi * u2);
}

float depthSigma(const SensorNoise& noise, float z) {
  return noise.sigma_0 + (noise.k_z1 + noise.k_z2 * z) * z;
}

bool isDepthEdge(const cv::Mat& true_depth, int x, int y) {
  const float z = true_depth.at<float>(y, x);
  if (z <= 0.0f) return false;
  const float threshold = 0.05f + 0.05f * z;
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  for (int k = 0; k < 4; ++k) {
    const int nx = x + dx[k], ny = y + dy[k];
    if (nx < 0 || ny < 0 || nx >= true_depth.cols || ny >= true_depth.rows) continue;
    const float zn = true_depth.at<float>(ny, nx);
    if (zn <= 0.0f || std::abs(zn - z) > threshold) return true;
  }
  return false;
}

namespace {

// The valid neighbour farthest in depth, for a flying pixel's mixed depth (z itself if none).
float farthestNeighbour(const cv::Mat& depth, int x, int y) {
  const float z = depth.at<float>(y, x);
  float best = z;
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  for (int k = 0; k < 4; ++k) {
    const int nx = x + dx[k], ny = y + dy[k];
    if (nx < 0 || ny < 0 || nx >= depth.cols || ny >= depth.rows) continue;
    const float zn = depth.at<float>(ny, nx);
    if (zn > 0.0f && std::abs(zn - z) > std::abs(best - z)) best = zn;
  }
  return best;
}

std::uint8_t toByte(float v) {
  return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

// The camera's 8-bit sRGB reading of `radiance`, with read noise of `sigma` codes drawn from `rng`
// when `noisy` (no draw otherwise, so the pixel's later draws stay where they were).
cv::Vec3b colourReading(const cv::Vec3f& radiance, float exposure, bool noisy, float sigma, PixelRng& rng) {
  cv::Vec3b bgr;
  for (int c = 0; c < 3; ++c) {
    const float encoded = 255.0f * linearToSrgb(std::max(0.0f, exposure * radiance[c]));
    bgr[c] = toByte(noisy ? encoded + sigma * rng.normal() : encoded);
  }
  return bgr;
}

}  // namespace

namespace {

struct ProfileName {
  SensorProfile profile;
  const char* name;
};
constexpr ProfileName kProfileNames[] = {{SensorProfile::uniform, "uniform"},
                                         {SensorProfile::structured_light, "structured-light"},
                                         {SensorProfile::stereo, "stereo"}};

float ramp(float value, float start, float end) {
  if (end <= start) return value >= end ? 1.0f : 0.0f;
  return std::clamp((value - start) / (end - start), 0.0f, 1.0f);
}

// Smooth value noise in [0, 1): uniform values on a lattice of `cell` pixels, interpolated with
// smoothstep weights. Thresholding it gives holes in patches instead of salt.
float patchNoise(std::uint64_t seed, float x, float y, float cell) {
  const float fx = x / cell, fy = y / cell;
  const int ix = static_cast<int>(std::floor(fx)), iy = static_cast<int>(std::floor(fy));
  const float tx = fx - static_cast<float>(ix), ty = fy - static_cast<float>(iy);
  const float sx = tx * tx * (3.0f - 2.0f * tx), sy = ty * ty * (3.0f - 2.0f * ty);
  const auto lattice = [&](int i, int j) { return PixelRng(seed, 0x9a7c4ull, i, j).uniform(); };
  const float top = lattice(ix, iy) + sx * (lattice(ix + 1, iy) - lattice(ix, iy));
  const float bottom = lattice(ix, iy + 1) + sx * (lattice(ix + 1, iy + 1) - lattice(ix, iy + 1));
  return top + sy * (bottom - top);
}

// Pixels the projector (or the second stereo camera), baseline metres along +x, cannot see: a
// point at column x and depth z appears at x - f b / z there, and a nearer point further right
// that lands at or left of it hides it. One scan per row from the projector's side.
cv::Mat projectorShadow(const cv::Mat& depth, float focal_px, float baseline) {
  cv::Mat shadow = cv::Mat::zeros(depth.size(), CV_8UC1);
  if (baseline <= 0.0f) return shadow;
  const float fb = focal_px * baseline;
  tbb::parallel_for(0, depth.rows, [&](int y) {
    float leftmost = std::numeric_limits<float>::infinity();
    for (int x = depth.cols - 1; x >= 0; --x) {
      const float z = depth.at<float>(y, x);
      if (z <= 0.0f) continue;
      const float projected = static_cast<float>(x) - fb / z;
      if (projected > leftmost) shadow.at<std::uint8_t>(y, x) = 255;
      leftmost = std::min(leftmost, projected);
    }
  });
  return shadow;
}

cv::Mat nearDepthEdges(const cv::Mat& depth, float band_px) {
  cv::Mat edges = cv::Mat::zeros(depth.size(), CV_8UC1);
  tbb::parallel_for(0, depth.rows, [&](int y) {
    for (int x = 0; x < depth.cols; ++x)
      if (isDepthEdge(depth, x, y)) edges.at<std::uint8_t>(y, x) = 255;
  });
  const int r = static_cast<int>(std::lround(band_px));
  if (r <= 0) return edges;
  cv::Mat near;
  cv::dilate(edges, near, cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * r + 1, 2 * r + 1}));
  return near;
}

// Local contrast of what the camera sees: standard deviation of the 8-bit sRGB luminance over
// 7 x 7 pixels, before colour noise (a stereo matcher cannot lock on sensor noise).
cv::Mat textureContrast(const cv::Mat& radiance, float exposure) {
  cv::Mat luminance(radiance.size(), CV_32FC1);
  for (int y = 0; y < radiance.rows; ++y)
    for (int x = 0; x < radiance.cols; ++x) {
      const cv::Vec3f& bgr = radiance.at<cv::Vec3f>(y, x);
      const float l = 0.0722f * bgr[0] + 0.7152f * bgr[1] + 0.2126f * bgr[2];
      luminance.at<float>(y, x) = 255.0f * linearToSrgb(std::max(0.0f, exposure * l));
    }
  cv::Mat mean, mean_sq;
  cv::boxFilter(luminance, mean, CV_32F, {7, 7});
  cv::boxFilter(luminance.mul(luminance), mean_sq, CV_32F, {7, 7});
  cv::Mat variance = mean_sq - mean.mul(mean);
  cv::Mat contrast;
  cv::sqrt(cv::max(variance, 0.0f), contrast);
  return contrast;
}

// The nearest valid depth within radius_px (both axes), for stereo's fattened foreground.
cv::Mat nearestDepth(const cv::Mat& depth, float radius_px) {
  const int r = static_cast<int>(std::lround(radius_px));
  cv::Mat far_holes = depth.clone();
  far_holes.setTo(std::numeric_limits<float>::max(), depth <= 0.0f);
  if (r <= 0) return far_holes;
  cv::Mat nearest;
  cv::erode(far_holes, nearest, cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * r + 1, 2 * r + 1}));
  return nearest;
}

SensorOutput applyProfiledSensor(const SensorNoise& noise, const CameraSettings& camera,
                                 const cv::Mat& true_depth, const cv::Mat& cos_incidence,
                                 const cv::Mat& radiance, std::uint64_t seed, std::uint64_t static_seed,
                                 const SurfaceMaps& surface) {
  SensorOutput out;
  out.depth = cv::Mat::zeros(true_depth.size(), CV_32FC1);
  out.colour = cv::Mat(true_depth.size(), CV_8UC3);
  const float focal_px =
      0.5f * static_cast<float>(camera.width) / std::tan(0.5f * camera.hfov_deg * kPi / 180.0f);
  const cv::Mat shadow = projectorShadow(true_depth, focal_px, noise.baseline);
  const cv::Mat near_edge = nearDepthEdges(true_depth, noise.edge_band_px);
  const bool stereo_texture = noise.low_texture_dropout > 0.0f;
  const cv::Mat contrast = stereo_texture ? textureContrast(radiance, camera.exposure) : cv::Mat();
  const bool fattening = noise.edge_fattening_px > 0.0f;
  const cv::Mat nearest = fattening ? nearestDepth(true_depth, noise.edge_fattening_px) : cv::Mat();
  const float fb = noise.native_focal_px * noise.baseline;
  const float patch = std::max(1.0f, noise.hole_patch_px);
  const bool has_surface = !surface.albedo.empty();
  if (has_surface)
    CV_Assert(surface.albedo.type() == CV_32FC1 && surface.metallic.type() == CV_32FC1 &&
              surface.roughness.type() == CV_32FC1 && surface.albedo.size() == true_depth.size() &&
              surface.metallic.size() == true_depth.size() && surface.roughness.size() == true_depth.size());
  tbb::parallel_for(0, true_depth.rows, [&](int y) {
    for (int x = 0; x < true_depth.cols; ++x) {
      PixelRng rng(seed, 0x5e4502ull, x, y);
      const cv::Vec3f& rad = radiance.at<cv::Vec3f>(y, x);
      out.colour.at<cv::Vec3b>(y, x) = colourReading(rad, camera.exposure, true, noise.colour_sigma, rng);
      const float z = true_depth.at<float>(y, x);
      if (!(z > 0.0f) || !std::isfinite(z) || shadow.at<std::uint8_t>(y, x)) continue;
      const float cosine = cos_incidence.at<float>(y, x);
      const float angle =
          std::acos(std::clamp(std::isfinite(cosine) ? cosine : 0.0f, 0.0f, 1.0f)) * 180.0f / kPi;
      const bool on_edge = near_edge.at<std::uint8_t>(y, x) != 0;
      float keep = 1.0f - ramp(angle, noise.grazing_start_deg, noise.grazing_dropout_deg);
      keep *= 1.0f - ramp(z, noise.range_fade_start, noise.range_fade_end);
      const float albedo = has_surface ? surface.albedo.at<float>(y, x)
                                       : 0.0722f * rad[0] + 0.7152f * rad[1] + 0.2126f * rad[2];
      keep *= 1.0f - noise.dark_dropout * (1.0f - ramp(albedo, 0.0f, noise.dark_luminance));
      if (has_surface) {
        const float roughness = std::clamp(surface.roughness.at<float>(y, x), 0.0f, 1.0f);
        keep *= 1.0f - noise.metal_dropout * std::clamp(surface.metallic.at<float>(y, x), 0.0f, 1.0f) *
                           (1.0f - roughness);
        keep *= 1.0f - noise.highlight_dropout * (1.0f - ramp(roughness, 0.0f, 0.5f)) *
                           (1.0f - ramp(angle, 0.0f, noise.highlight_deg));
      }
      if (on_edge) keep *= 1.0f - noise.edge_dropout;
      if (stereo_texture && contrast.at<float>(y, x) < noise.low_texture_contrast)
        keep *= 1.0f - noise.low_texture_dropout;
      const float fx = static_cast<float>(x), fy = static_cast<float>(y);
      const float pattern = (1.0f - noise.hole_flicker) * patchNoise(static_seed, fx, fy, patch) +
                            noise.hole_flicker * patchNoise(seed, fx, fy, patch);
      if (pattern < 1.0f - keep) continue;
      if (rng.uniform() < noise.random_dropout) continue;
      float base = z;
      if (fattening && nearest.at<float>(y, x) < z - (0.05f + 0.05f * z)) base = nearest.at<float>(y, x);
      if (on_edge && rng.uniform() < noise.flying_pixel)
        base = base + (0.15f + 0.7f * rng.uniform()) * (farthestNeighbour(true_depth, x, y) - base);
      float measured = base + depthSigma(noise, base) * rng.normal();
      if (fb > 0.0f && noise.disparity_step_px > 0.0f && measured > 0.0f) {
        const float steps = std::round(fb / measured / noise.disparity_step_px);
        measured = steps > 0.0f ? fb / (steps * noise.disparity_step_px) : 0.0f;
      }
      if (measured >= camera.min_range && measured <= camera.max_range) out.depth.at<float>(y, x) = measured;
    }
  });
  return out;
}

}  // namespace

const char* sensorProfileName(SensorProfile profile) {
  for (const auto& p : kProfileNames)
    if (p.profile == profile) return p.name;
  return "uniform";
}

std::vector<std::string> sensorProfileNames() {
  std::vector<std::string> names;
  for (const auto& p : kProfileNames) names.emplace_back(p.name);
  return names;
}

SensorProfile sensorProfileFromName(const std::string& name, const std::string& origin,
                                    const std::string& field) {
  for (const auto& p : kProfileNames)
    if (name == p.name) return p.profile;
  throw InputError(origin, field, "a sensor profile: uniform, structured-light or stereo", name);
}

SensorNoise sensorProfile(SensorProfile profile) {
  SensorNoise n;
  n.profile = profile;
  if (profile == SensorProfile::structured_light) {
    n.sigma_0 = 0.0f;
    n.k_z1 = 0.0014f;
    n.k_z2 = 0.0002f;
    n.disparity_step_px = 0.0625f;
    n.grazing_start_deg = 60.0f;
    n.grazing_dropout_deg = 80.0f;
    n.edge_dropout = 0.2f;
    n.edge_band_px = 1.0f;
    n.flying_pixel = 0.1f;
    n.random_dropout = 0.002f;
    n.dark_luminance = 0.02f;
    n.dark_dropout = 0.7f;
    n.metal_dropout = 0.9f;
    n.highlight_deg = 12.0f;
    n.highlight_dropout = 0.9f;
    n.range_fade_start = 3.3f;
    n.range_fade_end = 5.5f;
    n.hole_patch_px = 8.0f;
    n.hole_flicker = 0.3f;
  } else if (profile == SensorProfile::stereo) {
    n.sigma_0 = 0.001f;
    n.k_z2 = 0.004f;
    n.baseline = 0.12f;
    n.native_focal_px = 700.0f;
    n.disparity_step_px = 0.0f;
    n.grazing_start_deg = 70.0f;
    n.grazing_dropout_deg = 85.0f;
    n.edge_dropout = 0.2f;
    n.edge_band_px = 1.0f;
    n.flying_pixel = 0.0f;
    n.random_dropout = 0.002f;
    n.metal_dropout = 0.3f;  // a textureless metal surface mirrors a different scene into each camera
    n.highlight_deg = 20.0f;
    n.highlight_dropout = 0.6f;
    n.range_fade_start = 15.0f;
    n.range_fade_end = 20.0f;
    n.low_texture_contrast = 3.0f;
    n.low_texture_dropout = 0.4f;
    n.edge_fattening_px = 3.0f;
    n.hole_patch_px = 12.0f;
    n.hole_flicker = 0.3f;
  }
  return n;
}

SensorOutput applySensorNoise(const SensorNoise& noise, const CameraSettings& camera,
                              const cv::Mat& true_depth, const cv::Mat& cos_incidence,
                              const cv::Mat& radiance, std::uint64_t seed, std::uint64_t static_seed,
                              const SurfaceMaps& surface) {
  CV_Assert(true_depth.type() == CV_32FC1 && cos_incidence.type() == CV_32FC1 && radiance.type() == CV_32FC3);
  CV_Assert(true_depth.size() == cos_incidence.size() && true_depth.size() == radiance.size());
  if (noise.enabled && noise.profile != SensorProfile::uniform)
    return applyProfiledSensor(noise, camera, true_depth, cos_incidence, radiance, seed, static_seed,
                               surface);
  SensorOutput out;
  out.depth = cv::Mat::zeros(true_depth.size(), CV_32FC1);
  out.colour = cv::Mat(true_depth.size(), CV_8UC3);
  const float cos_grazing = std::cos(noise.grazing_dropout_deg * kPi / 180.0f);
  tbb::parallel_for(0, true_depth.rows, [&](int y) {
    for (int x = 0; x < true_depth.cols; ++x) {
      PixelRng rng(seed, 0x5e4502ull, x, y);
      out.colour.at<cv::Vec3b>(y, x) = colourReading(radiance.at<cv::Vec3f>(y, x), camera.exposure,
                                                     noise.enabled, noise.colour_sigma, rng);
      const float z = true_depth.at<float>(y, x);
      if (!noise.enabled) {
        out.depth.at<float>(y, x) = z;
        continue;
      }
      if (z <= 0.0f) continue;
      if (rng.uniform() < noise.random_dropout) continue;
      if (cos_incidence.at<float>(y, x) < cos_grazing) continue;
      float base = z;
      if (isDepthEdge(true_depth, x, y)) {
        if (rng.uniform() < noise.edge_dropout) continue;
        if (rng.uniform() < noise.flying_pixel)
          base = z + (0.15f + 0.7f * rng.uniform()) * (farthestNeighbour(true_depth, x, y) - z);
      }
      const float measured = base + depthSigma(noise, base) * rng.normal();
      if (measured >= camera.min_range && measured <= camera.max_range) out.depth.at<float>(y, x) = measured;
    }
  });
  return out;
}

}  // namespace holo::sim
