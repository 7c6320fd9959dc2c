#include "holo/depthfilter/temporal_depth_filter.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/depthfilter/precursor_flow.hpp"
#include "holo/depthfilter/reused_zero_image.hpp"

namespace holo::depthfilter {

// The pyramid's types live outside the anonymous namespace: the filter keeps a pyramid between
// frames (TemporalDepthFilter::Scratch).
namespace pyramid_detail {

// One (depth, confidence) pair of the pyramid rho_pa; depth 0 = no pair.
struct Pair {
  float depth = 0.0f;
  float confidence = 1.0f;
  float weight = 0.0f;          // pull-push weight: the summed reliabilities of the pixels behind it
  bool straddles_edge = false;  // the pulled block held surfaces farther apart than T(z)
  bool push_declined = false;   // no pair: the push declined it (or every parent it could come from)
  cv::Vec3f colour{};           // BGR, the weighted mean colour of the measured pixels behind it
  bool valid() const { return depth > 0.0f; }
};

struct Level {
  int width = 0;
  int height = 0;
  std::vector<Pair> pairs;
  Pair& at(int x, int y) { return pairs[static_cast<std::size_t>(y) * std::size_t(width) + std::size_t(x)]; }
};

}  // namespace pyramid_detail

struct TemporalDepthFilter::Scratch {
  cv::Mat clean, measured, pre_depth, alphas, pre_age, motion, motion_weight, inner, age, hole_reasons;
  std::vector<pyramid_detail::Level> pyramid;
  ReusedZeroImage output;  // the returned depth: non-zero only inside the work box
};

namespace {

using pyramid_detail::Level;
using pyramid_detail::Pair;

float sanitisedDepth(float d) {
  return std::isfinite(d) && d > 0.0f ? d : 0.0f;
}

void checkInput(const DepthFilterInput& in) {
  const cv::Size size = in.depth.size();
  if (in.depth.type() != CV_32FC1) throw Error("TemporalDepthFilter: expected CV_32FC1 depth");
  if (in.colour.type() != CV_8UC3 || in.colour.size() != size)
    throw Error("TemporalDepthFilter: expected CV_8UC3 colour of the depth's size");
  if (in.mask.type() != CV_8UC1 || in.mask.size() != size)
    throw Error("TemporalDepthFilter: expected a CV_8UC1 mask of the depth's size");
  if (in.flow.type() != CV_32FC2 || in.flow.size() != size)
    throw Error("TemporalDepthFilter: expected CV_32FC2 flow of the depth's size");
}

// The measured depth (into `out`, with `clean` as scratch) with flying pixels removed: a foreground depth
// counts only when at least `min_support` of its 8 neighbours lie on the same surface (within T(z)). A flying
// pixel lies between two surfaces and matches neither; a pixel of a real surface, even a 1-2 px wide arm, has
// neighbours along it. Works on `roi`, which holds the mask and one pixel around it (or touches the
// image's edge); `clean` and `out` are left as they were outside it.
void supportedDepth(const cv::Mat& depth, const cv::Mat& mask, const cv::Rect& roi,
                    const TemporalDepthFilterConfig& config, cv::Mat& clean, cv::Mat& out) {
  const int width = depth.cols, height = depth.rows;
  clean.create(depth.size(), CV_32FC1);
  for (int y = roi.y; y < roi.y + roi.height; ++y) {
    const float* in = depth.ptr<float>(y);
    float* c = clean.ptr<float>(y);
    for (int x = roi.x; x < roi.x + roi.width; ++x) c[x] = sanitisedDepth(in[x]);
  }
  out.create(depth.size(), CV_32FC1);
  // The support of the pixel at x of row `rows[1]`, counting only the neighbours that exist.
  const auto support_at_edge = [&](const float* const rows[3], int x, float d, float tolerance) {
    int support = 0;
    for (int r = 0; r < 3; ++r) {
      if (rows[r] == nullptr) continue;
      for (int nx = std::max(0, x - 1); nx <= std::min(width - 1, x + 1); ++nx)
        support += (r != 1 || nx != x) && std::abs(rows[r][nx] - d) <= tolerance;
    }
    return support;
  };
  const float tolerance_m = config.surface_tolerance_m, tolerance_z2 = config.surface_tolerance_z2;
  const int min_support = config.min_support;
  for (int y = roi.y; y < roi.y + roi.height; ++y) {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(y);
    const float* rows[3] = {y > 0 ? clean.ptr<float>(y - 1) : nullptr, clean.ptr<float>(y),
                            y + 1 < height ? clean.ptr<float>(y + 1) : nullptr};
    float* o = out.ptr<float>(y);
    const int x_end = roi.x + roi.width;
    // Pixels with all 8 neighbours inside the image: every pixel of the row is decided without
    // branches (the compiler vectorises it), the mask and a measurement selecting the result.
    const bool inner_row = rows[0] != nullptr && rows[2] != nullptr;
    const int inner_begin = inner_row ? std::max(roi.x, 1) : x_end;
    const int inner_end = inner_row ? std::min(x_end, width - 1) : x_end;
    for (int x = roi.x; x < std::min(inner_begin, x_end); ++x) {
      const float d = rows[1][x];
      const bool keep =
          m[x] != 0 && d > 0.0f && support_at_edge(rows, x, d, config.surfaceTolerance(d)) >= min_support;
      o[x] = keep ? d : 0.0f;
    }
    if (inner_begin < inner_end) {
      const float* __restrict up = rows[0];
      const float* __restrict mid = rows[1];
      const float* __restrict down = rows[2];
      float* __restrict o_row = o;
      for (int x = inner_begin; x < inner_end; ++x) {
        const float d = mid[x];
        const float tolerance = tolerance_m + tolerance_z2 * d * d;
        const int support = (std::abs(up[x - 1] - d) <= tolerance) + (std::abs(up[x] - d) <= tolerance) +
                            (std::abs(up[x + 1] - d) <= tolerance) + (std::abs(mid[x - 1] - d) <= tolerance) +
                            (std::abs(mid[x + 1] - d) <= tolerance) +
                            (std::abs(down[x - 1] - d) <= tolerance) + (std::abs(down[x] - d) <= tolerance) +
                            (std::abs(down[x + 1] - d) <= tolerance);
        o_row[x] = (m[x] != 0) & (d > 0.0f) & (support >= min_support) ? d : 0.0f;
      }
    }
    for (int x = std::max(inner_end, inner_begin); x < x_end; ++x) {
      const float d = rows[1][x];
      const bool keep =
          m[x] != 0 && d > 0.0f && support_at_edge(rows, x, d, config.surfaceTolerance(d)) >= min_support;
      o[x] = keep ? d : 0.0f;
    }
  }
}

// True when the measurements within `edge_radius` pixels of (x, y) span more than T(z): a hole
// there could belong to either surface, and a fill from the wrong one flickers between them.
bool nearDepthEdge(const cv::Mat& measured, int x, int y, const TemporalDepthFilterConfig& config) {
  float lo = INFINITY, hi = 0.0f;
  const int r = config.edge_radius;
  for (int ny = std::max(0, y - r); ny <= std::min(measured.rows - 1, y + r); ++ny)
    for (int nx = std::max(0, x - r); nx <= std::min(measured.cols - 1, x + r); ++nx) {
      const float d = measured.at<float>(ny, nx);
      if (d <= 0.0f) continue;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  return hi > 0.0f && hi - lo > config.surfaceTolerance(lo);
}

// True when the hole (x, y) lies between two surfaces: the first measurements met going left,
// right, up and down from it inside the mask span more than T(z). Such a hole is a gap through
// which something else shows (the space between two limbs, an arm and the torso), and with
// thin articulated visitors its neighbours' depth is that of the limbs in front, not of the
// gap: without a trusted precursor such fills were 50-80 cm in front of the truth in the museum.
// Scanning stops at the mask's edge, so it never leaves the work box.
bool betweenSurfaces(const cv::Mat& measured, const cv::Mat& mask, int x, int y,
                     const TemporalDepthFilterConfig& config) {
  float lo = INFINITY, hi = 0.0f;
  constexpr int kSteps[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (const auto& step : kSteps) {
    for (int nx = x + step[0], ny = y + step[1];
         nx >= 0 && ny >= 0 && nx < measured.cols && ny < measured.rows && mask.at<std::uint8_t>(ny, nx) != 0;
         nx += step[0], ny += step[1]) {
      const float d = measured.at<float>(ny, nx);
      if (d <= 0.0f) continue;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
      break;
    }
  }
  return hi > 0.0f && hi - lo > config.surfaceTolerance(lo);
}

// Age of an output depth: frames since the pixel's surface was last measured there (0 =
// measured in this frame). kNoDepth marks pixels without an output depth.
constexpr std::uint8_t kNoDepth = 255;

std::uint8_t olderBy1(std::uint8_t age) {
  return std::uint8_t(std::min<int>(kNoDepth - 1, age + 1));
}

float colourDistance(const cv::Vec3b& a, const cv::Vec3f& b) {
  return std::abs(float(a[0]) - b[0]) + std::abs(float(a[1]) - b[1]) + std::abs(float(a[2]) - b[2]);
}

// A hole the push could not fill safely: next to a depth edge, under a pulled block that
// straddles one, with a fill that its precursor contradicts, or in a block without any
// measurement. `pre` is the depth of its trusted precursor (0: none, then the hole lies away
// from depth edges, inside the mask or at its edge). The candidates are the measured neighbours within
// `fill_radius` px; the hole's own surface usually has its colour, so a surface of another colour
// (skin next to a shirt, the wall behind a visitor) does not count. Depth edges drop random
// pixels each frame, so such a hole was usually measured a frame ago, and the precursor confirms
// the surface. Returns 0 where no fill is safe, with the reason in `declined`.
float guidedHoleFill(const cv::Mat& measured, const Level& filtered, const cv::Mat& colour_image, int x,
                     int y, float pre, bool at_mask_edge, const TemporalDepthFilterConfig& config,
                     HoleReason& declined) {
  const int r = config.fill_radius;
  const int width = measured.cols, height = measured.rows;
  const cv::Vec3b colour = colour_image.at<cv::Vec3b>(y, x);
  struct Candidate {
    float depth;
    float colour;
  };
  constexpr int kMaxSide = 2 * TemporalDepthFilterConfig::kMaxFillRadius + 1;
  Candidate candidates[kMaxSide * kMaxSide];
  int n = 0;
  float best_colour = INFINITY, best_depth = 0.0f;
  for (int ny = std::max(0, y - r); ny <= std::min(height - 1, y + r); ++ny)
    for (int nx = std::max(0, x - r); nx <= std::min(width - 1, x + r); ++nx) {
      if (measured.at<float>(ny, nx) <= 0.0f) continue;
      const float d = filtered.pairs[std::size_t(ny) * std::size_t(width) + std::size_t(nx)].depth;
      if (!(d > 0.0f)) continue;
      candidates[n] = {d, colourDistance(colour, colour_image.at<cv::Vec3b>(ny, nx))};
      if (candidates[n].colour < best_colour) best_colour = candidates[n].colour, best_depth = d;
      ++n;
    }
  // No measured neighbour has the hole's colour: the hole shows a surface that is not measured
  // nearby (the grazing side of a visitor half hidden behind another); any fill would be wrong.
  if (n == 0 || best_colour > config.fill_colour_max) {
    declined = HoleReason::TrustedNoColourMatch;
    return 0.0f;
  }
  // The plausible neighbours are those about as alike in colour as the closest one. They must
  // all lie on the surface of the precursor (or, without one, of the closest neighbour): where
  // two surfaces of one colour meet (an arm in front of the torso), the flow's precursor picks
  // the wrong one too often near a moving edge (35-41% of such fills lie farther than T(z) from
  // the truth, 9 cm RMS, and they flicker: docs/depthfilter.md "Holes at the mask's edge and the
  // precursor's surface"), so such a hole stays a hole unless fill_on_precursor_surface takes
  // those on the precursor's surface.
  const float plausible = best_colour + config.fill_colour_margin;
  const float surface = pre > 0.0f ? pre : best_depth;
  const float tolerance = config.surfaceTolerance(surface);
  const bool leave_out_other_surfaces = pre > 0.0f && config.fill_on_precursor_surface;
  float sum = 0.0f, farthest = 0.0f;
  int count = 0;
  bool other_surface = false;
  for (int k = 0; k < n; ++k) {
    if (candidates[k].colour > plausible) continue;
    if (std::abs(candidates[k].depth - surface) > tolerance) {
      other_surface = true;
      if (!leave_out_other_surfaces) break;
      continue;
    }
    sum += candidates[k].depth;
    farthest = std::max(farthest, candidates[k].depth);
    ++count;
  }
  if ((other_surface && !leave_out_other_surfaces) || count == 0) {
    declined = HoleReason::TrustedOtherSurface;
    return 0.0f;
  }
  // At the mask's edge the surface turns away from the camera (the sensor read nothing there at
  // a grazing angle), so it lies behind its measured neighbours: the farthest of them is nearer
  // the truth than their mean (fills within T(z) of the truth 82% against 75%, museum CI size).
  return at_mask_edge ? farthest : sum / float(count);
}

// A hole between surfaces of its colour that the rules on this camera's pixels leave: its
// measured neighbours within fill_radius of about its colour (as guidedHoleFill's) grouped into
// surfaces (depths within T(z) of the group's nearest), asked nearest first of the witness: the
// first one seen is the fill, provided every nearer one was seen through; an undecided one ends
// the search (0: a hole).
float witnessedHoleFill(const cv::Mat& measured, const Level& filtered, const cv::Mat& colour_image, int x,
                        int y, const TemporalDepthFilterConfig& config, const SurfaceWitness& witness) {
  const int r = config.fill_radius;
  const int width = measured.cols, height = measured.rows;
  const cv::Vec3b colour = colour_image.at<cv::Vec3b>(y, x);
  constexpr int kMaxSide = 2 * TemporalDepthFilterConfig::kMaxFillRadius + 1;
  float depths[kMaxSide * kMaxSide], colours[kMaxSide * kMaxSide];
  int n = 0;
  float best_colour = INFINITY;
  for (int ny = std::max(0, y - r); ny <= std::min(height - 1, y + r); ++ny)
    for (int nx = std::max(0, x - r); nx <= std::min(width - 1, x + r); ++nx) {
      if (measured.at<float>(ny, nx) <= 0.0f) continue;
      const float d = filtered.pairs[std::size_t(ny) * std::size_t(width) + std::size_t(nx)].depth;
      if (!(d > 0.0f)) continue;
      depths[n] = d;
      colours[n] = colourDistance(colour, colour_image.at<cv::Vec3b>(ny, nx));
      best_colour = std::min(best_colour, colours[n]);
      ++n;
    }
  if (n == 0 || best_colour > config.fill_colour_max) return 0.0f;
  const float plausible = best_colour + config.fill_colour_margin;
  int m = 0;
  for (int k = 0; k < n; ++k)
    if (colours[k] <= plausible) depths[m++] = depths[k];
  std::sort(depths, depths + m);
  for (int first = 0; first < m;) {
    const float tolerance = config.surfaceTolerance(depths[first]);
    float sum = 0.0f;
    int last = first;
    while (last < m && depths[last] - depths[first] <= tolerance) sum += depths[last++];
    const float surface = sum / float(last - first);
    const Sighting sighting = witness.sighting(x, y, surface);
    if (sighting == Sighting::Seen) return surface;
    if (sighting != Sighting::Empty) return 0.0f;
    first = last;
  }
  return 0.0f;
}

// Reliability of a pair: 1 - c (smaller confidence values are more reliable), kept positive so
// that the least confident measurement still counts.
float reliability(float confidence) {
  constexpr float kEps = 1e-3f;
  return 1.0f - confidence + kEps;
}

// A measured pair's weight in the pull: every measurement counts, one with a reliable precursor
// (confidence 0) twice as much as one without (confidence 1).
float pullWeight(float confidence) {
  return 1.0f - 0.5f * confidence;
}

// Pull (Algorithm 1, lines 23-26), depth-aware: each parent is the reliability-weighted mean of
// the children that lie on the block's dominant surface, the child depth whose agreeing children
// (within T(z)) carry the most weight (ties: the nearer). Children on another surface (the wall
// behind a limb, an arm in front of the torso) are left out instead of averaged into a depth
// between the two, and mark the parent as straddling a depth edge. A parent's weight is the sum
// of its children's, so a block measured over more pixels outweighs a block with one. Only the
// parents in `parent_rect` are computed, from the children in `child_rect`; children outside it
// count as missing (they lie outside the work box).
void pull(const Level& child, const cv::Rect& child_rect, Level& parent, const cv::Rect& parent_rect,
          const TemporalDepthFilterConfig& config) {
  const int child_x_end = child_rect.x + child_rect.width, child_y_end = child_rect.y + child_rect.height;
  for (int y = parent_rect.y; y < parent_rect.y + parent_rect.height; ++y) {
    // The two child rows of the parent row (null outside child_rect).
    const Pair* rows[2];
    for (int dy = 0; dy < 2; ++dy) {
      const int cy = 2 * y + dy;
      rows[dy] = cy >= child_rect.y && cy < child_y_end
                     ? &child.pairs[std::size_t(cy) * std::size_t(child.width)]
                     : nullptr;
    }
    Pair* parent_row = &parent.pairs[std::size_t(y) * std::size_t(parent.width)];
    for (int x = parent_rect.x; x < parent_rect.x + parent_rect.width; ++x) {
      const Pair* block[4];
      int n = 0;
      bool child_straddles = false;
      for (const Pair* row : rows) {
        if (row == nullptr) continue;
        for (int cx = 2 * x; cx < 2 * x + 2; ++cx) {
          if (cx < child_rect.x || cx >= child_x_end || !row[cx].valid()) continue;
          block[n++] = &row[cx];
          child_straddles = child_straddles || row[cx].straddles_edge;
        }
      }
      Pair out;
      if (n > 0) {
        float surface = 0.0f, best_support = -1.0f;
        for (int k = 0; k < n; ++k) {
          const float tolerance = config.surfaceTolerance(block[k]->depth);
          float support = 0.0f;
          for (int j = 0; j < n; ++j)
            if (std::abs(block[j]->depth - block[k]->depth) <= tolerance) support += block[j]->weight;
          if (support > best_support || (support == best_support && block[k]->depth < surface)) {
            best_support = support;
            surface = block[k]->depth;
          }
        }
        const float tolerance = config.surfaceTolerance(surface);
        float sum_w = 0.0f, sum_d = 0.0f, sum_c = 0.0f;
        cv::Vec3f sum_colour{};
        bool other_surface = false;
        for (int k = 0; k < n; ++k) {
          const Pair& p = *block[k];
          if (std::abs(p.depth - surface) > tolerance) {
            other_surface = true;
            continue;
          }
          sum_w += p.weight;
          sum_d += p.weight * p.depth;
          sum_c += p.weight * p.confidence;
          sum_colour += p.weight * p.colour;
        }
        out = {sum_d / sum_w, sum_c / sum_w,     sum_w, child_straddles || other_surface,
               false,         sum_colour / sum_w};
      }
      parent_row[x] = out;
    }
  }
}

// Push (line 28). A missing pair is filled only where its neighbourhood agrees: the (up to) four
// parents nearest to it, bilinearly weighted, must all lie on one surface (within T(z)) and none
// may straddle a depth edge; the fill is their weighted mean. A hole beside a depth edge could
// belong to either surface, so it stays a hole for the final checks to decide (in the simulated
// museum a fill from the front surface put 15-20% of such pixels 20 cm or more off). Interpolating
// between parents instead of copying the one above keeps a fill from jumping by a block's depth
// gradient when the block grid slides over a moving body (the flicker of the blocky push). A
// present pair is blended with its own parent by reliabilities when both lie on one surface.
// Only the children in `child_rect`; parents outside `parent_rect` count as missing. With a
// `needed` mask (CV_8UC1 of the child's size), only the children it marks are pushed; the others
// are left as they were.
void push(const Level& parent, const cv::Rect& parent_rect, Level& child, const cv::Rect& child_rect,
          const TemporalDepthFilterConfig& config, const cv::Mat* needed = nullptr) {
  const auto parentAt = [&](int px, int py) -> const Pair* {
    if (px < parent_rect.x || py < parent_rect.y || px >= parent_rect.x + parent_rect.width ||
        py >= parent_rect.y + parent_rect.height)
      return nullptr;
    return &parent.pairs[std::size_t(py) * std::size_t(parent.width) + std::size_t(px)];
  };
  for (int y = child_rect.y; y < child_rect.y + child_rect.height; ++y) {
    // The two parent rows nearest to the child's centre and the weight of the second.
    const int py0 = (y - 1) >> 1;
    const float ty = (y & 1) == 0 ? 0.75f : 0.25f;
    const std::uint8_t* needed_row = needed != nullptr ? needed->ptr<std::uint8_t>(y) : nullptr;
    for (int x = child_rect.x; x < child_rect.x + child_rect.width; ++x) {
      if (needed_row != nullptr && needed_row[x] == 0) continue;
      Pair& c = child.at(x, y);
      if (c.valid()) {
        const Pair* p = parentAt(x / 2, y / 2);
        if (p == nullptr || !p->valid() || std::abs(c.depth - p->depth) > config.surfaceTolerance(c.depth))
          continue;
        const float wc = reliability(c.confidence), wp = reliability(p->confidence);
        c.depth = (wc * c.depth + wp * p->depth) / (wc + wp);
        c.confidence = (wc * c.confidence + wp * p->confidence) / (wc + wp);
        continue;
      }
      const int px0 = (x - 1) >> 1;
      const float tx = (x & 1) == 0 ? 0.75f : 0.25f;
      float sum_w = 0.0f, sum_d = 0.0f, sum_c = 0.0f, lo = INFINITY, hi = 0.0f;
      cv::Vec3f sum_colour{};
      bool agrees = true, parent_declined = false;
      for (int k = 0; k < 4 && agrees; ++k) {
        const int dx = k & 1, dy = k >> 1;
        const Pair* p = parentAt(px0 + dx, py0 + dy);
        if (p == nullptr) continue;
        if (!p->valid()) {
          parent_declined = parent_declined || p->push_declined;
          continue;
        }
        agrees = !p->straddles_edge;
        const float w = (dx != 0 ? tx : 1.0f - tx) * (dy != 0 ? ty : 1.0f - ty) * p->weight;
        sum_w += w;
        sum_d += w * p->depth;
        sum_c += w * p->confidence;
        sum_colour += w * p->colour;
        lo = std::min(lo, p->depth);
        hi = std::max(hi, p->depth);
      }
      if (sum_w <= 0.0f) {
        c.push_declined = parent_declined;
        continue;
      }
      if (!agrees || hi - lo > config.surfaceTolerance(lo)) {
        c.push_declined = true;
        continue;
      }
      c = {sum_d / sum_w, sum_c / sum_w, sum_w, false, false, sum_colour / sum_w};
    }
  }
}

// The part of the frame that the per-pixel passes work on. Outside the mask the output is 0,
// and a foreground pixel's output reads at most `reach` pixels around it: its 8 neighbours (flying
// pixels), the motion window, the depth-edge radius and the hole fill's radius. The box filter of
// the motion reflects its border within the box; twice the reach keeps the reflected values zero,
// as outside the mask. The pyramid needs nothing more than the push's spread: a pulled block
// outside the box holds no foreground pixel and so no pair, and the push's interpolation carries
// fills at most about 2^l_max pixels beyond the pulled pairs. Empty when the mask is.
cv::Rect workBox(const cv::Mat& mask, const TemporalDepthFilterConfig& config) {
  const cv::Rect frame(0, 0, mask.cols, mask.rows);
  if (!config.mask_box_only) return frame;
  const cv::Rect box = cv::boundingRect(mask);
  if (box.empty()) return box;
  const int reach = std::max({1, config.motion_window / 2, config.edge_radius, config.fill_radius});
  const int margin = std::max(2 * reach, 1 << config.levels);
  return cv::Rect(box.x - margin, box.y - margin, box.width + 2 * margin, box.height + 2 * margin) & frame;
}

}  // namespace

TemporalDepthFilter::TemporalDepthFilter(TemporalDepthFilterConfig config)
    : config_(config),
      pdf_alpha_(config.pdf_bins, config.alpha_max),
      pdf_depth_diff_(config.pdf_bins, config.depth_diff_max_m),
      scratch_ptr_(std::make_unique<Scratch>()) {
  if (config_.levels < 1 || config_.levels > TemporalDepthFilterConfig::kMaxLevels)
    throw Error("TemporalDepthFilter: levels (l_max) must be in [1, " +
                std::to_string(TemporalDepthFilterConfig::kMaxLevels) + "]");
  if (config_.learning_frames < 0) throw Error("TemporalDepthFilter: learning_frames (C) must be >= 0");
  if (config_.fill_radius < 0 || config_.fill_radius > TemporalDepthFilterConfig::kMaxFillRadius)
    throw Error("TemporalDepthFilter: fill_radius must be in [0, " +
                std::to_string(TemporalDepthFilterConfig::kMaxFillRadius) + "]");
}

TemporalDepthFilter::~TemporalDepthFilter() = default;

const cv::Mat& TemporalDepthFilter::holeReasons() const {
  return scratch_ptr_->hole_reasons;
}
TemporalDepthFilter::TemporalDepthFilter(TemporalDepthFilter&&) noexcept = default;
TemporalDepthFilter& TemporalDepthFilter::operator=(TemporalDepthFilter&&) noexcept = default;

bool TemporalDepthFilter::learning() const {
  return frame_ < config_.learning_frames || pdf_alpha_.samples() < config_.min_learning_samples ||
         pdf_depth_diff_.samples() < config_.min_learning_samples;
}

void TemporalDepthFilter::resetHistory() {
  previous_colour_.release();
  previous_depth_.release();
  previous_mask_.release();
  previous_age_.release();
}

cv::Mat TemporalDepthFilter::apply(const DepthFilterInput& in) {
  checkInput(in);
  const int width = in.depth.cols, height = in.depth.rows;
  if (!previous_depth_.empty() && previous_depth_.size() != in.depth.size()) resetHistory();
  const bool has_previous = !previous_depth_.empty();
  const bool learn = learning();
  Scratch& scratch = *scratch_ptr_;

  // Every per-pixel pass below works on `roi` only (see workBox); the scratch images hold stale
  // values outside it, which nothing reads.
  const cv::Rect roi = workBox(in.mask, config_);
  supportedDepth(in.depth, in.mask, roi, config_, scratch.clean, scratch.measured);
  const cv::Mat& measured = scratch.measured;
  // GetPrePx (line 7) for every foreground pixel: the precursor must lie in the image, on the
  // previous foreground and carry a depth; it is used only on the same surface (within T(z)).
  cv::Mat& pre_depth = scratch.pre_depth;
  cv::Mat& alphas = scratch.alphas;
  cv::Mat& pre_age = scratch.pre_age;
  cv::Mat& motion = scratch.motion;  // d - d_pre where both exist
  cv::Mat& motion_weight = scratch.motion_weight;
  for (cv::Mat* m : {&pre_depth, &alphas, &motion, &motion_weight}) m->create(height, width, CV_32FC1);
  pre_age.create(height, width, CV_8UC1);
  // One pass writes every pixel of the box: the precursor's values where there is one, else the
  // values of "none" (0 and kNoDepth).
  for (int y = roi.y; y < roi.y + roi.height; ++y) {
    const float* depth = measured.ptr<float>(y);
    const std::uint8_t* mask = in.mask.ptr<std::uint8_t>(y);
    const cv::Vec3b* colour = in.colour.ptr<cv::Vec3b>(y);
    const cv::Vec2f* flow = in.flow.ptr<cv::Vec2f>(y);
    float* pre_row = pre_depth.ptr<float>(y);
    float* alpha_row = alphas.ptr<float>(y);
    std::uint8_t* pre_age_row = pre_age.ptr<std::uint8_t>(y);
    float* motion_row = motion.ptr<float>(y);
    float* motion_weight_row = motion_weight.ptr<float>(y);
    for (int x = roi.x; x < roi.x + roi.width; ++x) {
      pre_row[x] = alpha_row[x] = motion_row[x] = motion_weight_row[x] = 0.0f;
      pre_age_row[x] = kNoDepth;
      if (!has_previous || mask[x] == 0 || !std::isfinite(flow[x][0]) || !std::isfinite(flow[x][1])) continue;
      const int px = nearestPixel(float(x) + flow[x][0]);
      const int py = nearestPixel(float(y) + flow[x][1]);
      if (px < 0 || py < 0 || px >= width || py >= height || previous_mask_.ptr<std::uint8_t>(py)[px] == 0)
        continue;
      const float d_pre = previous_depth_.ptr<float>(py)[px];
      if (!(d_pre > 0.0f)) continue;
      pre_row[x] = d_pre;
      pre_age_row[x] = previous_age_.ptr<std::uint8_t>(py)[px];
      alpha_row[x] = precursorConfidence(colour[x], previous_colour_.ptr<cv::Vec3b>(py)[px]);
      if (depth[x] > 0.0f && std::abs(depth[x] - d_pre) <= config_.surfaceTolerance(d_pre)) {
        motion_row[x] = depth[x] - d_pre;
        motion_weight_row[x] = 1.0f;
      }
    }
  }
  // The flow gives only the motion in the image; a visitor walking towards the camera also moves
  // in depth. The local mean of d - d_pre over the same surface is that motion, and adding it to
  // d_pre keeps the recursion from lagging one frame of depth motion behind.
  if (has_previous && config_.motion_window > 1 && !roi.empty()) {
    const cv::Size window(config_.motion_window, config_.motion_window);
    const int border = cv::BORDER_REFLECT_101 | cv::BORDER_ISOLATED;
    cv::Mat motion_roi = motion(roi), motion_weight_roi = motion_weight(roi);
    cv::boxFilter(motion_roi, motion_roi, -1, window, cv::Point(-1, -1), false, border);
    cv::boxFilter(motion_weight_roi, motion_weight_roi, -1, window, cv::Point(-1, -1), false, border);
  }

  // The pyramid's levels keep their storage from frame to frame.
  std::vector<Level>& pyramid = scratch.pyramid;
  if (pyramid.empty()) pyramid.resize(1);
  Level& base = pyramid.front();
  base.width = width;
  base.height = height;
  base.pairs.resize(std::size_t(width) * std::size_t(height));
  cv::Mat output = scratch.output.next(cv::Size(width, height), CV_32FC1);
  scratch.output.written(roi);  // every pass below writes inside it only
  // Frames since each output depth was last measured (0: measured in this frame); while
  // learning, every passed-through depth counts as measured. Read only on the mask, so only the
  // box is set.
  cv::Mat& age = scratch.age;
  age.create(height, width, CV_8UC1);
  age(roi).setTo(learn ? 0 : kNoDepth);
  for (int y = roi.y; y < roi.y + roi.height; ++y) {
    const float* depth = measured.ptr<float>(y);
    const std::uint8_t* mask = in.mask.ptr<std::uint8_t>(y);
    float* pre_row = pre_depth.ptr<float>(y);
    const float* alpha_row = alphas.ptr<float>(y);
    const float* motion_row = motion.ptr<float>(y);
    const float* motion_weight_row = motion_weight.ptr<float>(y);
    const cv::Vec3b* colour_row = in.colour.ptr<cv::Vec3b>(y);
    Pair* pair_row = &base.pairs[std::size_t(y) * std::size_t(width)];
    for (int x = roi.x; x < roi.x + roi.width; ++x) {
      Pair& pair = pair_row[x];
      pair = Pair{};  // no pair unless set below
      if (mask[x] == 0) continue;
      const float d = depth[x];
      float d_pre = pre_row[x];
      const float weight = motion_weight_row[x];
      if (d_pre > 0.0f && weight > 0.0f) d_pre += motion_row[x] / weight;
      pre_row[x] = d_pre;  // motion-compensated, for the hole fill below
      const bool has_pre = d_pre > 0.0f && d > 0.0f && std::abs(d - d_pre) <= config_.surfaceTolerance(d_pre);
      const float diff = std::abs(d - d_pre);
      const float alpha = alpha_row[x];
      if (learn) {  // lines 11-16: learn the PDFs, pass the frame through
        if (has_pre) {
          pdf_depth_diff_.add(diff);
          pdf_alpha_.add(alpha);
        }
        output.ptr<float>(y)[x] = sanitisedDepth(in.depth.ptr<float>(y)[x]);  // gamma_i as it came
        continue;
      }
      // A pixel without a measurement gets no pair and is filled by the push from the current
      // frame's neighbours; carrying d_pre instead would freeze a hole at a stale depth
      // (docs/depthfilter.md, "Holes").
      if (has_pre) {
        const float p_diff = pdf_depth_diff_.cdf(diff);  // line 19
        const float confidence = pdf_alpha_.cdf(alpha);
        pair = {(1.0f - p_diff) * d + p_diff * d_pre,
                confidence,
                pullWeight(confidence),
                false,
                false,
                cv::Vec3f(colour_row[x])};  // lines 18-21
      } else if (d > 0.0f) {
        pair = {
            d,     1.0f,  pullWeight(1.0f),
            false, false, cv::Vec3f(colour_row[x])};  // no usable precursor: the measurement, least confident
      }
    }
  }

  if (config_.record_hole_reasons) scratch.hole_reasons = cv::Mat::zeros(height, width, CV_8UC1);
  if (!learn && !roi.empty()) {
    std::vector<cv::Rect> rects{roi};  // the work box at each level
    std::size_t top = 0;
    for (int l = 1; l < config_.levels; ++l) {
      if (pyramid[top].width == 1 && pyramid[top].height == 1) break;
      if (pyramid.size() == top + 1) pyramid.emplace_back();
      Level& parent = pyramid[top + 1];
      parent.width = (pyramid[top].width + 1) / 2;
      parent.height = (pyramid[top].height + 1) / 2;
      parent.pairs.resize(std::size_t(parent.width) * std::size_t(parent.height));
      const cv::Rect child_rect = rects.back();  // a copy: the emplace below may move the vector
      const int x0 = child_rect.x / 2, y0 = child_rect.y / 2;
      const int x1 = (child_rect.x + child_rect.width + 1) / 2,
                y1 = (child_rect.y + child_rect.height + 1) / 2;
      rects.emplace_back(x0, y0, x1 - x0, y1 - y0);
      pull(pyramid[top], child_rect, parent, rects.back(), config_);
      ++top;
    }
    // The base level is read only on the mask (the final pass below and the hole fill's
    // measured neighbours), so only its pixels are pushed there.
    for (std::size_t l = top; l > 0; --l)
      push(pyramid[l], rects[l], pyramid[l - 1], rects[l - 1], config_, l == 1 ? &in.mask : nullptr);
    const Level& filtered = pyramid.front();
    cv::Mat* reasons = config_.record_hole_reasons ? &scratch.hole_reasons : nullptr;
    // Pixels farther than edge_radius inside the mask: a hole there lies within the measured
    // surface around it. Nearer the mask's edge, the surface may continue unmeasured (a body's
    // side turning away at a grazing angle) and a fill needs a trusted precursor.
    cv::Mat& inner = scratch.inner;
    inner.create(height, width, CV_8UC1);
    cv::Mat inner_roi = inner(roi);
    const int side = 2 * config_.edge_radius + 1;
    cv::erode(in.mask(roi), inner_roi, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side)),
              cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    for (int y = roi.y; y < roi.y + roi.height; ++y) {
      const std::uint8_t* mask = in.mask.ptr<std::uint8_t>(y);
      const std::uint8_t* inside = inner.ptr<std::uint8_t>(y);
      const float* measured_row = measured.ptr<float>(y);
      const float* pre_row = pre_depth.ptr<float>(y);
      const std::uint8_t* pre_age_row = pre_age.ptr<std::uint8_t>(y);
      float* out = output.ptr<float>(y);
      std::uint8_t* out_age = age.ptr<std::uint8_t>(y);
      for (int x = roi.x; x < roi.x + roi.width; ++x) {
        if (mask[x] == 0) continue;
        const Pair& pushed = filtered.pairs[std::size_t(y) * std::size_t(width) + std::size_t(x)];
        const float d = pushed.depth;
        if (measured_row[x] > 0.0f) {
          out[x] = std::isfinite(d) && d > 0.0f ? d : 0.0f;
          out_age[x] = 0;
          continue;
        }
        // A hole. Its precursor is trusted when it was measured at most fill_trust_frames - 1
        // frames ago: fills that only repeat fills would keep a wrong pick alive.
        const float pre = pre_row[x];
        const bool trusted = pre > 0.0f && pre_age_row[x] < config_.fill_trust_frames;
        float fill = 0.0f;
        bool used_push = false;
        bool witnessed = false;
        HoleReason declined = HoleReason::None;
        if (trusted) {
          // Its surface, from the neighbours of its colour on it. The push's fill is not used
          // here: agreeing with the precursor within T(z) still let it pick the wrong one of two
          // surfaces of one colour near a moving edge (docs/depthfilter.md, "Pull-push").
          fill = guidedHoleFill(measured, filtered, in.colour, x, y, pre, false, config_, declined);
        } else if (inside[x] == 0 && !config_.fill_mask_edge) {
          declined = HoleReason::MaskEdge;
        } else if (nearDepthEdge(measured, x, y, config_)) {
          declined = HoleReason::DepthEdge;
        } else if (inside[x] == 0) {
          // At the mask's edge: only from the measured neighbours of its colour, all on one
          // surface; they lie inside the mask, on the visitor's side of the edge. Never the
          // push's fill, whose coarse levels average the body's interior into the edge.
          fill = guidedHoleFill(measured, filtered, in.colour, x, y, 0.0f, true, config_, declined);
          if (fill <= 0.0f) declined = HoleReason::MaskEdge;
        } else {
          // Inside a surface: the neighbours with the hole's colour within fill_radius, else the
          // push's fill where the measured pixels it comes from have the hole's colour (the
          // pyramid reaches holes wider than fill_radius).
          fill = guidedHoleFill(measured, filtered, in.colour, x, y, 0.0f, false, config_, declined);
          if (fill <= 0.0f) {
            if (!pushed.valid()) {
              declined = pushed.push_declined ? HoleReason::PushDisagrees : HoleReason::PushOutOfReach;
            } else if (colourDistance(in.colour.ptr<cv::Vec3b>(y)[x], pushed.colour) >
                       config_.fill_colour_max + config_.fill_colour_margin) {
              declined = HoleReason::PushOtherColour;
            } else {
              fill = pushed.depth;
              used_push = true;
            }
          }
        }
        // Without a recent measurement of its own, nothing says which surface a hole between
        // two surfaces shows (the trusted precursor does: an edge dropout measured a frame ago).
        if (fill > 0.0f && !trusted && betweenSurfaces(measured, in.mask, x, y, config_)) {
          fill = 0.0f;
          declined = HoleReason::BetweenSurfaces;
        }
        // Two surfaces of its colour (or none it may take) beside it: another camera decides.
        if (fill <= 0.0f && in.witness != nullptr && config_.fill_witnessed &&
            (declined == HoleReason::TrustedOtherSurface || declined == HoleReason::DepthEdge ||
             declined == HoleReason::BetweenSurfaces || declined == HoleReason::MaskEdge)) {
          fill = witnessedHoleFill(measured, filtered, in.colour, x, y, config_, *in.witness);
          witnessed = fill > 0.0f;
        }
        if (reasons != nullptr && fill <= 0.0f) reasons->ptr<std::uint8_t>(y)[x] = std::uint8_t(declined);
        if (fill > 0.0f) {
          out[x] = fill;
          // The push's and the witness's fills are no precursor to trust (the witness decides
          // again next frame).
          out_age[x] =
              used_push || witnessed ? std::uint8_t(config_.fill_trust_frames) : olderBy1(pre_age_row[x]);
        }
      }
    }
  }

  // The next frame reads the previous colour, depth and age only where the previous mask is
  // foreground, which lies inside the box: only the box is kept (the mask is kept whole).
  previous_colour_.create(height, width, CV_8UC3);
  previous_depth_.create(height, width, CV_32FC1);
  if (previous_mask_.size() != in.mask.size())
    previous_mask_ = cv::Mat::zeros(height, width, CV_8UC1);
  else if (!previous_roi_.empty())
    previous_mask_(previous_roi_).setTo(0);
  if (!roi.empty()) {
    in.colour(roi).copyTo(previous_colour_(roi));
    output(roi).copyTo(previous_depth_(roi));
    in.mask(roi).copyTo(previous_mask_(roi));
  }
  previous_roi_ = roi;
  std::swap(previous_age_, age);
  ++frame_;
  return output;
}

}  // namespace holo::depthfilter
