#include "holo/reflect/hit_points.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <optional>
#include <span>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/reflect/surface_shading.hpp"
#include "holo/reflect/view.hpp"

namespace holo::reflect {
namespace {

// Below this cosine two neighbouring normals are a crease (~18 degrees): the reflected image
// jumps there, and a single centre sample would alias it.
constexpr float kCreaseCos = 0.95f;
// Roughness or base colour apart by more than this: a material edge.
constexpr float kMaterialStep = 0.1f;

// The hit point where the primary `ray` through a view's pixel met the relic; returns whether
// it is a usable one (h is written only for a hit).
bool resolveHitPoint(const RenderScene& scene, const RayScene& relic, const CameraModel& view, const Ray& ray,
                     const RayHit& hit, HitPoint& h) {
  if (!hit.hit()) return false;
  const SurfacePoint s = resolveSurface(scene, relic, ray, hit, hit.t / view.intrinsics().fx);
  h.position = s.position;
  h.normal = s.normal;
  h.to_viewer = -ray.direction;
  h.reflected = glm::reflect(ray.direction, h.normal);
  h.clearcoat_normal = s.clearcoat_normal;
  h.material = s.material;
  h.emission = s.emission;
  h.occlusion = s.occlusion;
  h.alpha = s.alpha;
  h.location = s.location;
  h.gltf = &scene.relicGltfMaterial(hit, relic);
  h.mirror_may_meet_relic = scene.mayMeetRelicAgain(hit, h.reflected);
  return isFinite(h.position) && isFinite(h.normal) && isFinite(h.reflected);
}

// Traces one sample; returns whether it hit the relic (h is written only then).
bool traceSample(const RenderScene& scene, const RayScene& relic, const CameraModel& view, const vec2& pixel,
                 HitPoint& h) {
  const Ray ray = primaryRay(view, pixel);
  return resolveHitPoint(scene, relic, view, ray, relic.intersect(ray, 0.0f, 1e30f, PartialHits::Solid), h);
}

// Primary rays cast together (coherent packets), at most this many at a time per task.
constexpr std::size_t kBatch = 64;

// Traces the samples at `pixels` (view pixel coordinates) into hits[i] and valid[i] (1: a
// usable hit point), their rays cast kBatch at a time in coherent packets.
void traceSamples(const RenderScene& scene, const RayScene& relic, const CameraModel& view,
                  std::span<const vec2> pixels, HitPoint* hits, std::uint8_t* valid) {
  std::array<Ray, kBatch> rays;
  std::array<RayHit, kBatch> ray_hits;
  for (std::size_t first = 0; first < pixels.size(); first += kBatch) {
    const std::size_t n = std::min(kBatch, pixels.size() - first);
    for (std::size_t i = 0; i < n; ++i) rays[i] = primaryRay(view, pixels[first + i]);
    relic.intersectCoherent(std::span(rays).first(n), std::span(ray_hits).first(n), 0.0f, 1e30f,
                            PartialHits::Solid);
    for (std::size_t i = 0; i < n; ++i)
      valid[first + i] = resolveHitPoint(scene, relic, view, rays[i], ray_hits[i], hits[first + i]) ? 1 : 0;
  }
}

bool differ(const HitPointBuffer& b, std::size_t p, std::size_t q) {
  if (b.valid[p] != b.valid[q]) return true;
  if (!b.valid[p]) return false;
  const HitPoint& a = b.hits[p];
  const HitPoint& c = b.hits[q];
  if (glm::dot(a.normal, c.normal) < kCreaseCos) return true;
  if (std::abs(a.material.roughness - c.material.roughness) > kMaterialStep) return true;
  const vec3 d = glm::abs(a.material.base_colour - c.material.base_colour);
  return std::max(d.x, std::max(d.y, d.z)) > kMaterialStep;
}

// The pixels whose rays (and sub-sample rays) may hit the box; the whole image when that
// cannot be bounded cheaply.
cv::Rect candidatePixels(const CameraModel& view, const Bounds3& box) {
  const cv::Rect all(0, 0, view.width(), view.height());
  if (box.empty() || view.intrinsics().hasDistortion()) return all;
  float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
  for (int corner = 0; corner < 8; ++corner) {
    const vec3 p((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                 (corner & 4) ? box.hi.z : box.lo.z);
    float depth = 0.0f;
    const std::optional<vec2> px = view.project(p, &depth);
    if (!px || !(depth > 0.0f)) return all;
    x0 = std::min(x0, px->x);
    y0 = std::min(y0, px->y);
    x1 = std::max(x1, px->x);
    y1 = std::max(y1, px->y);
  }
  // One pixel of margin covers the sub-sample offsets (< 0.5 pixel) and round-off.
  const int left = int(std::floor(x0)) - 1, top = int(std::floor(y0)) - 1;
  const int right = int(std::ceil(x1)) + 2, bottom = int(std::ceil(y1)) + 2;
  return cv::Rect(left, top, right - left, bottom - top) & all;
}

// Per row y of the view, the columns [begin[y], end[y]) to trace (begin >= end: none).
struct RowSpans {
  std::vector<int> begin, end;
};

// The box's rectangle, narrowed per row to the union of the projected bounding boxes of the
// relic's triangles (a pinhole ray hits a triangle only inside its projection), grown by two
// pixels (the sub-sample offsets, round-off, and the neighbours the edge test compares) and by
// the rows above and below. A vase seen from the side fills about 40% of its box's rectangle:
// the rest of the rectangle's rays all missed. The rectangle alone when a vertex is not in front
// of the view or the view has distortion; the whole image without a box.
RowSpans candidateSpans(const RayScene& relic, const CameraModel& view, const Bounds3& box) {
  const cv::Rect rect = candidatePixels(view, box);
  const int h = view.height();
  RowSpans spans{std::vector<int>(std::size_t(h), 0), std::vector<int>(std::size_t(h), 0)};
  const auto whole_rect = [&] {
    for (int y = rect.y; y < rect.y + rect.height; ++y) {
      spans.begin[std::size_t(y)] = rect.x;
      spans.end[std::size_t(y)] = rect.x + rect.width;
    }
    return spans;
  };
  if (rect.empty() || box.empty() || view.intrinsics().hasDistortion()) return whole_rect();
  constexpr int kGrow = 2;
  std::vector<int> lo(std::size_t(h), std::numeric_limits<int>::max()), hi(std::size_t(h), -1);
  std::vector<vec2> projected;
  for (std::size_t g = 0; g < relic.meshCount(); ++g) {
    const TriangleMesh& mesh = relic.mesh(std::uint32_t(g));
    projected.resize(mesh.positions.size());
    std::atomic<bool> behind{false};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, projected.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) {
                          float depth = 0.0f;
                          const std::optional<vec2> px = view.project(mesh.positions[i], &depth);
                          if (!px || !(depth > 0.0f) || !std::isfinite(px->x) || !std::isfinite(px->y)) {
                            behind = true;
                            return;
                          }
                          projected[i] = *px;
                        }
                      });
    if (behind) return whole_rect();
    for (const uvec3& t : mesh.triangles) {
      const vec2 &a = projected[t.x], &b = projected[t.y], &c = projected[t.z];
      const float y0 = std::min({a.y, b.y, c.y}), y1 = std::max({a.y, b.y, c.y});
      const int top = std::max(int(std::floor(y0)) - kGrow, rect.y);
      const int bottom = std::min(int(std::ceil(y1)) + kGrow, rect.y + rect.height - 1);
      if (top > bottom) continue;
      const int left = int(std::floor(std::min({a.x, b.x, c.x}))) - kGrow;
      const int right = int(std::ceil(std::max({a.x, b.x, c.x}))) + kGrow + 1;
      for (int y = top; y <= bottom; ++y) {
        lo[std::size_t(y)] = std::min(lo[std::size_t(y)], left);
        hi[std::size_t(y)] = std::max(hi[std::size_t(y)], right);
      }
    }
  }
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    spans.begin[std::size_t(y)] = std::max(lo[std::size_t(y)], rect.x);
    spans.end[std::size_t(y)] = std::min(hi[std::size_t(y)], rect.x + rect.width);
  }
  return spans;
}

}  // namespace

AntiAliasing parseAntiAliasing(const std::string& text, const std::string& field) {
  if (text == "none") return AntiAliasing::None;
  if (text == "edges") return AntiAliasing::Edges;
  if (text == "full") return AntiAliasing::Full;
  throw InputError(field, "anti-aliasing", "none, edges or full", text);
}

const char* antiAliasingName(AntiAliasing mode) {
  switch (mode) {
    case AntiAliasing::None:
      return "none";
    case AntiAliasing::Edges:
      return "edges";
    case AntiAliasing::Full:
      return "full";
  }
  return "?";
}

std::vector<vec2> subsamplePattern(int samples) {
  if (samples == 1) return {vec2(0.0f)};
  if (samples == 4)  // rotated grid: distinct x and y offsets catch near-axis edges
    return {vec2(-0.125f, -0.375f), vec2(0.375f, -0.125f), vec2(0.125f, 0.375f), vec2(-0.375f, 0.125f)};
  throw InputError("tracer settings", "aa_samples", "1 or 4", std::to_string(samples));
}

float HitPointBuffer::coverage(int x, int y) const {
  const std::size_t p = std::size_t(y) * std::size_t(width) + std::size_t(x);
  const std::size_t first = firstSample(p);
  const int count = sampleCount(p);
  int n = 0;
  for (int s = 0; s < count; ++s) n += valid[first + std::size_t(s)];
  return float(n) / float(count);
}

void traceHitPoints(const RenderScene& scene, const CameraModel& view, AntiAliasing aa, HitPointBuffer& buf,
                    const Bounds3& relic_bounds) {
  const int w = view.width(), h = view.height();
  buf.width = w;
  buf.height = h;
  const std::size_t pixels = buf.pixelCount();
  const RayScene& relic = scene.relicOnly();
  buf.hits.resize(pixels);
  buf.valid.assign(pixels, 0);
  buf.first_sub.assign(pixels, HitPointBuffer::kCentreOnly);
  buf.refined.clear();
  const RowSpans traced = candidateSpans(relic, view, relic_bounds);
  const auto begin = [&](int y) { return traced.begin[std::size_t(y)]; };
  const auto end = [&](int y) { return traced.end[std::size_t(y)]; };
  // The most this trace can hold is every span pixel refined. Reserved with a quarter more, so
  // that a trace refining more pixels than every earlier one does not move the buffers (and the
  // per-sample ones that follow their capacity, HitPointBuffer::reservePerSample) to twice their
  // size: at 540x540 such a move copied and faulted in some 50 MB within one frame. Reserved pages
  // never written stay virtual.
  std::size_t span_pixels = 0;
  for (int y = 0; y < h; ++y) span_pixels += std::size_t(std::max(0, end(y) - begin(y)));
  const std::size_t most = pixels + 4 * span_pixels;
  if (buf.hits.capacity() < most) {
    buf.hits.reserve(most + most / 4);
    buf.valid.reserve(most + most / 4);
  }

  if (aa == AntiAliasing::Full) {
    for (int y = 0; y < h; ++y)
      for (int x = begin(y); x < end(y); ++x)
        buf.refined.push_back(static_cast<std::uint32_t>(std::size_t(y) * std::size_t(w) + std::size_t(x)));
  } else {
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
      std::vector<vec2> row_pixels;
      for (int y = rows.begin(); y < rows.end(); ++y) {
        if (begin(y) >= end(y)) continue;
        row_pixels.clear();
        for (int x = begin(y); x < end(y); ++x) row_pixels.emplace_back(float(x), float(y));
        const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(begin(y));
        traceSamples(scene, relic, view, row_pixels, &buf.hits[p], &buf.valid[p]);
      }
    });
    if (aa == AntiAliasing::Edges) {
      // Each neighbour pair is compared once: pixel p keeps one bit per pair with its right,
      // lower-left, lower and lower-right neighbours (rows in parallel, each writing its own
      // pixels), and is an edge when any of its eight pairs differs. Row y's pairs cover its
      // span and the next row's, one pixel wider (everything outside the spans missed); only
      // pixels inside the spans are flagged.
      enum : std::uint8_t { kRight = 1, kDownLeft = 2, kDown = 4, kDownRight = 8 };
      std::vector<std::uint8_t> pairs(pixels, 0);
      tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
          int x0 = begin(y), x1 = end(y);
          if (y + 1 < h && begin(y + 1) < end(y + 1)) {
            x0 = x0 < x1 ? std::min(x0, begin(y + 1)) : begin(y + 1);
            x1 = std::max(x1, end(y + 1));
          }
          if (x0 >= x1) continue;
          for (int x = std::max(x0 - 1, 0); x < std::min(x1 + 1, w); ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
            std::uint8_t bits = 0;
            if (x + 1 < w && differ(buf, p, p + 1)) bits |= kRight;
            if (y + 1 < h) {
              const std::size_t below = p + std::size_t(w);
              if (x > 0 && differ(buf, p, below - 1)) bits |= kDownLeft;
              if (differ(buf, p, below)) bits |= kDown;
              if (x + 1 < w && differ(buf, p, below + 1)) bits |= kDownRight;
            }
            pairs[p] = bits;
          }
        }
      });
      // first_sub doubles as the edge flag here (any value but kCentreOnly).
      tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
          for (int x = begin(y); x < end(y); ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
            bool edge = pairs[p] != 0 || (x > 0 && (pairs[p - 1] & kRight));
            if (y > 0 && !edge) {
              const std::size_t above = p - std::size_t(w);
              edge = (pairs[above] & kDown) || (x > 0 && (pairs[above - 1] & kDownRight)) ||
                     (x + 1 < w && (pairs[above + 1] & kDownLeft));
            }
            if (edge) buf.first_sub[p] = 0;
          }
      });
      for (std::size_t p = 0; p < pixels; ++p)
        if (buf.first_sub[p] != HitPointBuffer::kCentreOnly)
          buf.refined.push_back(static_cast<std::uint32_t>(p));
    }
  }

  const std::size_t total = pixels + 4 * buf.refined.size();
  buf.hits.resize(total);
  buf.valid.resize(total, 0);
  std::fill(buf.valid.begin() + std::ptrdiff_t(pixels), buf.valid.end(), std::uint8_t(0));
  const std::vector<vec2> pattern = subsamplePattern(4);
  // A refined pixel's four sub-samples, and those of its neighbours in the list, in packets.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buf.refined.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<vec2> samples;
                      samples.reserve(4 * r.size());
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const std::size_t p = buf.refined[k];
                        buf.first_sub[p] = static_cast<std::uint32_t>(pixels + 4 * k);
                        const vec2 centre(float(p % std::size_t(w)), float(p / std::size_t(w)));
                        for (std::size_t s = 0; s < 4; ++s) samples.push_back(centre + pattern[s]);
                      }
                      const std::size_t first = pixels + 4 * r.begin();
                      traceSamples(scene, relic, view, samples, &buf.hits[first], &buf.valid[first]);
                    });
  buf.covered.clear();
  for (int y = 0; y < h; ++y)
    for (int x = begin(y); x < end(y); ++x)
      if (buf.coverage(x, y) > 0.0f)
        buf.covered.push_back(static_cast<std::uint32_t>(std::size_t(y) * std::size_t(w) + std::size_t(x)));
}

bool traceHitPoint(const RenderScene& scene, const CameraModel& view, const vec2& pixel, HitPoint& out) {
  return traceSample(scene, scene.relicOnly(), view, pixel, out);
}

}  // namespace holo::reflect
