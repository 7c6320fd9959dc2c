#include "holo/display/eye_tracker.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/core/stats.hpp"

namespace holo::display {

namespace {

constexpr double kFallbackFrameS = 1.0 / 30.0;
constexpr float kSqrt2 = 1.41421356f;

// Horizontal grid of head_radius cells over the square |x|, |z| <= half_extent (the tracker adds
// only points within max_distance of the axis), so a head's neighbours lie in the 3x3 cells
// around it. Points are bucketed by a counting sort once all are added (finish()): a cell's
// points are contiguous, with no per-cell allocation.
class ColumnGrid {
 public:
  ColumnGrid(float cell, float half_extent)
      : cell_(cell), offset_(int(std::ceil(half_extent / cell)) + 1), side_(2 * offset_ + 1) {}
  void add(const vec3& p) { added_.push_back(p); }
  void finish() {
    start_.assign(std::size_t(side_) * std::size_t(side_) + 1, 0);
    for (const vec3& p : added_) ++start_[cellOf(p) + 1];
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    points_.resize(added_.size());
    std::vector<std::size_t> next(start_.begin(), start_.end() - 1);
    for (const vec3& p : added_) points_[next[cellOf(p)]++] = p;
  }
  // Points within `radius` horizontally of `top` and `depth` below it.
  std::vector<vec3> column(const vec3& top, float radius, float depth) const {
    std::vector<vec3> out;
    const int ci = index(top.x), ck = index(top.z);
    for (int i = std::max(ci - 1, 0); i <= std::min(ci + 1, side_ - 1); ++i)
      for (int k = std::max(ck - 1, 0); k <= std::min(ck + 1, side_ - 1); ++k) {
        const std::size_t c = std::size_t(k) * std::size_t(side_) + std::size_t(i);
        for (std::size_t j = start_[c]; j < start_[c + 1]; ++j) {
          const vec3& p = points_[j];
          const float dx = p.x - top.x, dz = p.z - top.z;
          if (dx * dx + dz * dz <= radius * radius && p.y <= top.y && p.y >= top.y - depth) out.push_back(p);
        }
      }
    return out;
  }

 private:
  int index(float v) const { return std::clamp(int(std::floor(v / cell_)) + offset_, 0, side_ - 1); }
  std::size_t cellOf(const vec3& p) const {
    return std::size_t(index(p.z)) * std::size_t(side_) + std::size_t(index(p.x));
  }
  float cell_;
  int offset_, side_;
  std::vector<vec3> added_, points_;
  std::vector<std::size_t> start_;  // cell c's points: points_[start_[c], start_[c + 1])
};

float horizontalDistance(const vec3& a, const vec3& b) {
  return std::hypot(a.x - b.x, a.z - b.z);
}

void checkFace(int face) {
  if (face < 0 || face >= kFaceCount)
    throw Error("display: face index " + std::to_string(face) + " outside 0..3");
}

}  // namespace

vec3 faceNormal(int face) {
  checkFace(face);
  static constexpr float kX[kFaceCount] = {0.0f, 1.0f, 0.0f, -1.0f};
  static constexpr float kZ[kFaceCount] = {1.0f, 0.0f, -1.0f, 0.0f};
  return {kX[face], 0.0f, kZ[face]};
}

vec3 defaultEye(int face, const EyeTrackerSettings& settings) {
  return faceNormal(face) * settings.default_distance +
         vec3(0.0f, settings.floor_y + settings.default_eye_height, 0.0f);
}

namespace {

// One pass over the cloud: per face, the finite points in its sector (a point on a diagonal is
// in both), at a head's height band and within the distance ring, in cloud order.
std::array<std::vector<vec3>, kFaceCount> headBandPoints(const depthfilter::ForegroundCloud& cloud,
                                                         const EyeTrackerSettings& settings) {
  const float y_lo = settings.floor_y + settings.min_head_top - settings.head_depth;
  const float y_hi = settings.floor_y + settings.max_head_top;
  std::array<std::vector<vec3>, kFaceCount> bands;
  std::array<vec3, kFaceCount> normals, tangents;
  for (int f = 0; f < kFaceCount; ++f) {
    normals[std::size_t(f)] = faceNormal(f);
    tangents[std::size_t(f)] = vec3(normals[std::size_t(f)].z, 0.0f, -normals[std::size_t(f)].x);
  }
  // Fixed chunks of the cloud in parallel, each keeping its points in cloud order; the chunks'
  // bands are joined in chunk order, so every band is the one a single pass gives.
  constexpr std::size_t kChunk = 8192;
  const std::size_t chunks = (cloud.points.size() + kChunk - 1) / kChunk;
  std::vector<std::array<std::vector<vec3>, kFaceCount>> chunk_bands(chunks);
  std::vector<std::int64_t> chunk_non_finite(chunks, 0);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    std::array<std::vector<vec3>, kFaceCount>& part = chunk_bands[c];
    const std::size_t first = c * kChunk, last = std::min(first + kChunk, cloud.points.size());
    for (std::size_t i = first; i < last; ++i) {
      const vec3& p = cloud.points[i].position;
      if (!isFinite(p)) {
        ++chunk_non_finite[c];
        continue;
      }
      if (p.y < y_lo || p.y > y_hi) continue;
      const float distance = std::hypot(p.x, p.z);
      if (distance < settings.min_distance || distance > settings.max_distance) continue;
      for (std::size_t f = 0; f < part.size(); ++f) {
        const float along = p.x * normals[f].x + p.z * normals[f].z;
        const float across = p.x * tangents[f].x + p.z * tangents[f].z;
        // A head whose top is in the sector is measured whole: its points up to head_radius past
        // the sector's border come along (inSector picks the tops).
        if (along > 0.0f && along - std::abs(across) >= -kSqrt2 * settings.head_radius) part[f].push_back(p);
      }
    }
  });
  std::int64_t non_finite = 0;
  for (std::size_t c = 0; c < chunks; ++c) {
    non_finite += chunk_non_finite[c];
    for (std::size_t f = 0; f < bands.size(); ++f)
      bands[f].insert(bands[f].end(), chunk_bands[c][f].begin(), chunk_bands[c][f].end());
  }
  if (non_finite > 0) stats::add("Display/Eye tracker non-finite points ignored", non_finite);
  return bands;
}

// Horizontal unit vector across the line from the pyramid's axis to `p` (the base cameras' rays
// run along that line, so depth noise and flying pixels spread along it, not across).
vec3 acrossTheRays(const vec3& p) {
  const float radial = std::hypot(p.x, p.z);
  return radial > 0.0f ? vec3(p.z / radial, 0.0f, -p.x / radial) : vec3(1.0f, 0.0f, 0.0f);
}

// The span [lo, hi] across the rays of the surface under `top`: the points of `head` between
// width_band_top and width_band_bottom below it, sorted across, grown from the top's own position
// both ways until a gap wider than max_surface_gap (so a raised arm beside the head, or the head
// beside an arm, is a separate piece). `top` is a head's top if that piece is at least
// min_head_width wide and the top lies over its middle half; a raised forearm or hand is thinner.
std::optional<std::pair<float, float>> headSpan(const std::vector<vec3>& head, const vec3& top,
                                                const EyeTrackerSettings& settings) {
  const vec3 across = acrossTheRays(top);
  std::vector<float> slice;
  for (const vec3& p : head)
    if (p.y <= top.y - settings.width_band_top && p.y >= top.y - settings.width_band_bottom)
      slice.push_back(p.x * across.x + p.z * across.z);
  if (slice.empty()) return std::nullopt;
  std::sort(slice.begin(), slice.end());
  const float at = top.x * across.x + top.z * across.z;
  // Start from the slice point nearest the top, across.
  std::size_t first = std::size_t(std::lower_bound(slice.begin(), slice.end(), at) - slice.begin());
  if (first == slice.size() || (first > 0 && at - slice[first - 1] < slice[first] - at)) --first;
  if (std::abs(slice[first] - at) > settings.max_surface_gap) return std::nullopt;
  std::size_t last = first;
  while (first > 0 && slice[first] - slice[first - 1] <= settings.max_surface_gap) --first;
  while (last + 1 < slice.size() && slice[last + 1] - slice[last] <= settings.max_surface_gap) ++last;
  const float lo = slice[first], hi = slice[last], width = hi - lo;
  if (width < settings.min_head_width || std::abs(at - 0.5f * (lo + hi)) > 0.25f * width) return std::nullopt;
  return std::pair<float, float>(lo, hi);
}

bool inSector(const vec3& p, int face) {
  const vec3 normal = faceNormal(face);
  const float along = p.x * normal.x + p.z * normal.z;
  const float across = p.x * normal.z - p.z * normal.x;
  return along > 0.0f && along >= std::abs(across);
}

std::optional<vec3> detectEyeAmong(const std::vector<vec3>& band, int face,
                                   const EyeTrackerSettings& settings, const std::optional<vec3>& near) {
  std::vector<vec3> candidates;
  ColumnGrid grid(settings.head_radius, settings.max_distance);
  for (const vec3& p : band) {
    grid.add(p);
    // A head's top must itself be at a plausible head height.
    if (p.y >= settings.floor_y + settings.min_head_top && inSector(p, face)) candidates.push_back(p);
  }
  grid.finish();
  // Candidates are visited from the highest down and the first few usually make a head: a heap
  // hands them out in that order without sorting all of them. Ties in height go by x, then z,
  // so the order never depends on the cloud's point order.
  const auto lower = [](const vec3& a, const vec3& b) {
    return a.y != b.y ? a.y < b.y : a.x != b.x ? a.x < b.x : a.z < b.z;
  };
  std::make_heap(candidates.begin(), candidates.end(), lower);
  std::size_t popped = 0;  // the `popped` highest sit at the end, highest last
  const auto highest = [&](std::size_t i) -> const vec3& {
    for (; popped <= i; ++popped)
      std::pop_heap(candidates.begin(), candidates.end() - std::ptrdiff_t(popped), lower);
    return candidates[candidates.size() - 1 - i];
  };

  const auto headAt = [&](const vec3& top) -> std::optional<vec3> {
    std::vector<vec3> head = grid.column(top, settings.head_radius, settings.head_depth);
    if (static_cast<int>(head.size()) < settings.min_support) return std::nullopt;
    const auto near_top = std::count_if(head.begin(), head.end(),
                                        [&](const vec3& p) { return p.y >= top.y - settings.top_band; });
    if (near_top < settings.min_top_support) return std::nullopt;
    const auto span = headSpan(head, top, settings);
    if (!span) {
      stats::add("Display/Eye tracker thin tops rejected (raised arms)", 1);
      return std::nullopt;
    }
    // The centroid of the head's own piece: an arm beside it stays out.
    const vec3 across = acrossTheRays(top);
    vec3 sum(0.0f);
    int count = 0;
    for (const vec3& p : head) {
      const float s = p.x * across.x + p.z * across.z;
      if (s < span->first - settings.max_surface_gap || s > span->second + settings.max_surface_gap) continue;
      sum += p;
      ++count;
    }
    const vec3 centroid = sum / static_cast<float>(count);
    return vec3(centroid.x, top.y - settings.eye_below_top, centroid.z);
  };
  // Candidates go from the highest down; a rejected one is a stray point (too little support).
  const auto search = [&](bool gated) -> std::optional<vec3> {
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const vec3& top = highest(i);
      if (gated && horizontalDistance(top, *near) > settings.gate) continue;
      if (auto eye = headAt(top)) return eye;
    }
    return std::nullopt;
  };
  if (near) {
    if (auto eye = search(true)) return eye;
  }
  return search(false);
}

}  // namespace

std::optional<vec3> detectEye(const depthfilter::ForegroundCloud& cloud, int face,
                              const EyeTrackerSettings& settings, const std::optional<vec3>& near) {
  checkFace(face);
  return detectEyeAmong(headBandPoints(cloud, settings)[std::size_t(face)], face, settings, near);
}

EyeTracker::EyeTracker(EyeTrackerSettings settings) : settings_(settings) {
  if (!(settings_.alpha > 0.0f && settings_.alpha <= 1.0f) ||
      !(settings_.beta >= 0.0f && settings_.beta < 2.0f))
    throw Error("display: eye tracker gains need 0 < alpha <= 1 and 0 <= beta < 2");
  if (!(settings_.reference_interval_s > 0.0 && std::isfinite(settings_.reference_interval_s)))
    throw Error("display: eye tracker reference_interval_s needs a finite number of seconds > 0");
  for (int f = 0; f < kFaceCount; ++f) eyes_[static_cast<std::size_t>(f)].position = defaultEye(f, settings_);
}

const std::array<FaceEye, kFaceCount>& EyeTracker::update(const depthfilter::ForegroundCloud& cloud) {
  double now = cloud.time_s;
  if (last_time_s_ && !(std::isfinite(now) && now > *last_time_s_)) now = *last_time_s_ + kFallbackFrameS;
  if (!std::isfinite(now)) now = 0.0;
  last_time_s_ = now;
  // One pass sorts the cloud's head-height points by face; the faces' detections are then
  // independent: in parallel. The filter updates after them, in face order, so the result does
  // not depend on the threads.
  const std::array<std::vector<vec3>, kFaceCount> bands = headBandPoints(cloud, settings_);
  std::array<std::optional<vec3>, kFaceCount> detections;
  tbb::parallel_for(0, kFaceCount, [&](int f) {
    const FaceEye& eye = eyes_[static_cast<std::size_t>(f)];
    std::optional<vec3> predicted;
    if (eye.tracked) predicted = eye.position + eye.velocity * static_cast<float>(now - eye.last_seen_s);
    detections[static_cast<std::size_t>(f)] =
        detectEyeAmong(bands[static_cast<std::size_t>(f)], f, settings_, predicted);
  });
  for (int f = 0; f < kFaceCount; ++f) updateFace(f, detections[static_cast<std::size_t>(f)], now);
  return eyes_;
}

void EyeTracker::updateFace(int face, const std::optional<vec3>& detection, double now) {
  FaceEye& eye = eyes_[static_cast<std::size_t>(face)];
  if (!detection) {
    // A missed frame holds the eye where it was (no extrapolation into nowhere); the filter
    // predicts over the whole gap at the next detection. After the timeout: the default eye.
    if (eye.tracked && now - eye.last_seen_s > settings_.lost_timeout_s)
      eye = FaceEye{defaultEye(face, settings_)};
    return;
  }
  const float step = static_cast<float>(now - eye.last_seen_s);
  const vec3 predicted = eye.position + eye.velocity * step;
  if (!eye.tracked || glm::length(*detection - predicted) > settings_.gate) {
    eye.position = *detection;  // a new visitor: start where they are, at rest
    eye.velocity = vec3(0.0f);
  } else {
    // The gains are set for updates every reference_interval_s; a longer step keeps the filter's
    // bandwidth and damping (alpha ~ step, beta ~ step^2), else a fixed-gain filter updated at
    // 10 Hz lags a visitor on the curve around the pyramid by acceleration * step^2 / beta:
    // 1 m/s^2 * (0.1 s)^2 / 0.05 = 0.2 m.
    const float scale = std::max(1.0f, step / static_cast<float>(settings_.reference_interval_s));
    const float alpha = std::min(1.0f, settings_.alpha * scale);
    const float beta = std::min(1.0f, settings_.beta * scale * scale);
    const vec3 residual = *detection - predicted;
    eye.position = predicted + alpha * residual;
    eye.velocity += (beta / step) * residual;
    const float speed = glm::length(eye.velocity);
    if (speed > settings_.max_speed) eye.velocity *= settings_.max_speed / speed;
  }
  eye.tracked = true;
  eye.last_seen_s = now;
}

}  // namespace holo::display
