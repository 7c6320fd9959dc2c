#include "holo/display/eye_tracker.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/core/stats.hpp"

namespace holo::display {

namespace {

constexpr double kFallbackFrameS = 1.0 / 30.0;
constexpr float kSqrt2 = 1.41421356f;

// Grid of head_radius x head_radius columns (at multiples of head_radius in x and z) over the
// points added, each cut into slabs of `slab` metres of height, so a head's neighbours lie in the
// 3x3 columns around it and a read of a height range touches only its slabs: a face whose band
// has no head tries every candidate top, a thousand reads in a frame, each over a visitor's whole
// upper body without the slabs. Points are bucketed by a counting sort once all are added
// (finish()): a cell's points are contiguous, in the order added, with no per-cell allocation.
class ColumnGrid {
 public:
  ColumnGrid(float cell, float slab) : cell_(cell), slab_(slab) {}
  void add(const vec3& p) { added_.push_back(p); }
  void finish() {
    if (!added_.empty()) {
      vec3 lo = added_.front(), hi = added_.front();
      for (const vec3& p : added_) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
      i_min_ = cellIndex(lo.x);
      k_min_ = cellIndex(lo.z);
      columns_x_ = cellIndex(hi.x) - i_min_ + 1;
      columns_z_ = cellIndex(hi.z) - k_min_ + 1;
      y_min_ = lo.y;
      slabs_ = 1 + int(std::floor((hi.y - y_min_) / slab_));
    }
    start_.assign(std::size_t(columns_x_) * std::size_t(columns_z_) * std::size_t(slabs_) + 1, 0);
    for (const vec3& p : added_) ++start_[cellOf(p) + 1];
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    points_.resize(added_.size());
    std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
    for (std::size_t n = 0; n < added_.size(); ++n)
      points_[next[cellOf(added_[n])]++] = {added_[n], static_cast<std::uint32_t>(n)};
  }
  // Calls f(added) for every point within `radius` horizontally of `top` with a height in
  // [y_lo, y_hi], column by column.
  template <class F>
  void forEachIn(const vec3& top, float radius, float y_lo, float y_hi, F&& f) const {
    forEachColumn(top, [&](int i, int k) {
      for (const Added& a : read(i, k, y_lo, y_hi))
        if (inColumn(a.p, top, radius, y_lo, y_hi)) f(a);
    });
  }
  std::size_t count(const vec3& top, float radius, float y_lo, float y_hi) const {
    std::size_t n = 0;
    forEachIn(top, radius, y_lo, y_hi, [&](const Added&) { ++n; });
    return n;
  }
  // Points within `radius` horizontally of `top` and `depth` below it, column by column and in
  // the order they were added within a column (the order the head's sums see).
  std::vector<vec3> column(const vec3& top, float radius, float depth) const {
    std::vector<vec3> out;
    std::vector<Added> in_column;
    const float y_lo = top.y - depth;
    forEachColumn(top, [&](int i, int k) {
      in_column.clear();
      for (const Added& a : read(i, k, y_lo, top.y))
        if (inColumn(a.p, top, radius, y_lo, top.y)) in_column.push_back(a);
      std::sort(in_column.begin(), in_column.end(), [](const Added& a, const Added& b) { return a.n < b.n; });
      for (const Added& a : in_column) out.push_back(a.p);
    });
    return out;
  }

 private:
  struct Added {
    vec3 p;
    std::uint32_t n;  // the order it was added in
  };
  static bool inColumn(const vec3& p, const vec3& top, float radius, float y_lo, float y_hi) {
    const float dx = p.x - top.x, dz = p.z - top.z;
    return dx * dx + dz * dz <= radius * radius && p.y <= y_hi && p.y >= y_lo;
  }
  template <class F>
  void forEachColumn(const vec3& top, F&& f) const {
    const int ci = cellIndex(top.x) - i_min_, ck = cellIndex(top.z) - k_min_;
    for (int i = std::max(ci - 1, 0); i <= std::min(ci + 1, columns_x_ - 1); ++i)
      for (int k = std::max(ck - 1, 0); k <= std::min(ck + 1, columns_z_ - 1); ++k) f(i, k);
  }
  // Column (i, k)'s points in the slabs that [y_lo, y_hi] reaches, slab by slab: one contiguous
  // run, as a column's slabs are consecutive cells.
  std::span<const Added> read(int i, int k, float y_lo, float y_hi) const {
    if (slabs_ == 0 || y_hi < y_lo) return {};
    const int first = slabOf(y_lo), last = slabOf(y_hi);
    const std::size_t column =
        (std::size_t(k) * std::size_t(columns_x_) + std::size_t(i)) * std::size_t(slabs_);
    return {points_.data() + start_[column + std::size_t(first)],
            points_.data() + start_[column + std::size_t(last) + 1]};
  }
  int cellIndex(float v) const { return int(std::floor(v / cell_)); }
  int slabOf(float y) const { return std::clamp(int(std::floor((y - y_min_) / slab_)), 0, slabs_ - 1); }
  std::size_t cellOf(const vec3& p) const {
    const std::size_t column =
        std::size_t(cellIndex(p.z) - k_min_) * std::size_t(columns_x_) + std::size_t(cellIndex(p.x) - i_min_);
    return column * std::size_t(slabs_) + std::size_t(slabOf(p.y));
  }
  float cell_, slab_;
  int i_min_ = 0, k_min_ = 0, columns_x_ = 0, columns_z_ = 0;  // the columns the points cover
  float y_min_ = 0.0f;
  int slabs_ = 0;
  std::vector<vec3> added_;
  std::vector<Added> points_;
  std::vector<std::uint32_t> start_;  // cell c's points: points_[start_[c], start_[c + 1])
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

// The span [lo, hi] across the rays of the surface under `top`: the points of its head (within
// head_radius of it and head_depth below it) between width_band_top and width_band_bottom below it, sorted
// across, grown from the top's own position both ways until a gap wider than max_surface_gap (so a raised arm
// beside the head, or the head beside an arm, is a separate piece). `top` is a head's top if that piece is at
// least min_head_width wide and the top lies over its middle half; a raised forearm or hand is thinner.
std::optional<std::pair<float, float>> headSpan(const ColumnGrid& grid, const vec3& top,
                                                const EyeTrackerSettings& settings) {
  const vec3 across = acrossTheRays(top);
  std::vector<float> slice;
  const float y_lo = std::max(top.y - settings.head_depth, top.y - settings.width_band_bottom);
  const float y_hi = std::min(top.y, top.y - settings.width_band_top);
  grid.forEachIn(top, settings.head_radius, y_lo, y_hi,
                 [&](const auto& a) { slice.push_back(a.p.x * across.x + a.p.z * across.z); });
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
  // Slabs of top_band: the thinnest height range a head's test reads.
  ColumnGrid grid(settings.head_radius, std::max(settings.top_band, 0.01f));
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

  // The head's support is counted before its points are gathered in order (only the head found
  // needs them): most tops tried are rejected.
  static auto& thin_tops = stats::counter("Display/Eye tracker thin tops rejected (raised arms)");
  const auto headAt = [&](const vec3& top) -> std::optional<vec3> {
    const float head_bottom = top.y - settings.head_depth;
    if (static_cast<int>(grid.count(top, settings.head_radius, head_bottom, top.y)) < settings.min_support)
      return std::nullopt;
    const std::size_t near_top =
        grid.count(top, settings.head_radius, std::max(head_bottom, top.y - settings.top_band), top.y);
    if (static_cast<int>(near_top) < settings.min_top_support) return std::nullopt;
    const auto span = headSpan(grid, top, settings);
    if (!span) {
      thin_tops.fetch_add(1, std::memory_order_relaxed);
      return std::nullopt;
    }
    const std::vector<vec3> head = grid.column(top, settings.head_radius, settings.head_depth);
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
