#include "holo/depthfilter/temporal_depth_filter.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/depthfilter/precursor_flow.hpp"

namespace holo::depthfilter {

namespace {

// One (depth, confidence) pair of the pyramid rho_pa; depth 0 = no pair.
struct Pair {
  float depth = 0.0f;
  float confidence = 1.0f;
  bool straddles_edge = false;  // the pulled block held surfaces farther apart than T(z)
  bool valid() const { return depth > 0.0f; }
};

struct Level {
  int width = 0;
  int height = 0;
  std::vector<Pair> pairs;
  Pair& at(int x, int y) { return pairs[static_cast<std::size_t>(y) * std::size_t(width) + std::size_t(x)]; }
};

float sanitisedDepth(float d) {
  return std::isfinite(d) && d > 0.0f ? d : 0.0f;
}

void checkInput(const DepthFilterInput& in) {
  const cv::Size size = in.depth.size();
  if (in.depth.type() != CV_32FC1) throw Error("TemporalDepthFilter: expected CV_32FC1 depth");
  if (in.color.type() != CV_8UC3 || in.color.size() != size)
    throw Error("TemporalDepthFilter: expected CV_8UC3 colour of the depth's size");
  if (in.mask.type() != CV_8UC1 || in.mask.size() != size)
    throw Error("TemporalDepthFilter: expected a CV_8UC1 mask of the depth's size");
  if (in.flow.type() != CV_32FC2 || in.flow.size() != size)
    throw Error("TemporalDepthFilter: expected CV_32FC2 flow of the depth's size");
}

// The measured depth with flying pixels removed: a foreground depth counts only when at least
// `min_support` of its 8 neighbours lie on the same surface (within T(z)). A flying pixel lies
// between two surfaces and matches neither; a pixel of a real surface, even a 1-2 px wide arm,
// has neighbours along it.
cv::Mat supportedDepth(const cv::Mat& depth, const cv::Mat& mask, const TemporalDepthFilterConfig& config) {
  const int width = depth.cols, height = depth.rows;
  cv::Mat clean(depth.size(), CV_32FC1);
  for (int y = 0; y < height; ++y) {
    float* out = clean.ptr<float>(y);
    for (int x = 0; x < width; ++x) out[x] = sanitisedDepth(depth.at<float>(y, x));
  }
  cv::Mat out = cv::Mat::zeros(depth.size(), CV_32FC1);
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < width; ++x) {
      const float d = clean.at<float>(y, x);
      if (m[x] == 0 || d <= 0.0f) continue;
      const float tolerance = config.surfaceTolerance(d);
      int support = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          support += std::abs(clean.at<float>(ny, nx) - d) <= tolerance;
        }
      if (support >= config.min_support) out.at<float>(y, x) = d;
    }
  }
  return out;
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

// Pull (Algorithm 1, lines 23-26): each parent averages the children whose confidence is within
// `tolerance` of the block's minimum.
void pull(const Level& child, Level& parent, const TemporalDepthFilterConfig& config) {
  const float tolerance = config.min_confidence_tolerance;
  for (int y = 0; y < parent.height; ++y) {
    for (int x = 0; x < parent.width; ++x) {
      Pair block[4];
      int n = 0;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const int cx = 2 * x + dx, cy = 2 * y + dy;
          if (cx >= child.width || cy >= child.height) continue;
          const Pair& p = child.pairs[std::size_t(cy) * std::size_t(child.width) + std::size_t(cx)];
          if (p.valid()) block[n++] = p;
        }
      Pair out;
      if (n > 0) {
        float min_c = block[0].confidence;
        for (int k = 1; k < n; ++k) min_c = std::min(min_c, block[k].confidence);
        // Among those, only the front-most surface: averaging across a depth edge would invent
        // a "flying" depth between the surfaces that the push would then spread into holes.
        float front = INFINITY;
        for (int k = 0; k < n; ++k)
          if (block[k].confidence <= min_c + tolerance) front = std::min(front, block[k].depth);
        const float front_limit = front + config.surfaceTolerance(front);
        float sum_d = 0.0f, sum_c = 0.0f;
        int used = 0;
        for (int k = 0; k < n; ++k) {
          if (block[k].confidence > min_c + tolerance || block[k].depth > front_limit) continue;
          sum_d += block[k].depth;
          sum_c += block[k].confidence;
          ++used;
        }
        float back = 0.0f;
        bool child_straddles = false;
        for (int k = 0; k < n; ++k) {
          back = std::max(back, block[k].depth);
          child_straddles = child_straddles || block[k].straddles_edge;
        }
        out = {sum_d / float(used), sum_c / float(used),
               child_straddles || back - front > config.surfaceTolerance(front)};
      }
      parent.at(x, y) = out;
    }
  }
}

// Push (line 28): fill a missing pair from the parent; blend a present one with the parent by
// reliabilities (1 - c) when both lie on one surface.
void push(const Level& parent, Level& child, const TemporalDepthFilterConfig& config) {
  constexpr float kEps = 1e-3f;  // keeps the weights positive when both confidences are 1
  for (int y = 0; y < child.height; ++y) {
    for (int x = 0; x < child.width; ++x) {
      const Pair& p = parent.pairs[std::size_t(y / 2) * std::size_t(parent.width) + std::size_t(x / 2)];
      Pair& c = child.at(x, y);
      if (!p.valid()) continue;
      if (!c.valid()) {
        // A hole under a block that straddles a depth edge could belong to either surface:
        // filling it with the front one put 15-20% of such pixels 20 cm or more off in the
        // simulated museum, so it stays a hole (docs/depthfilter.md, "Holes").
        if (!p.straddles_edge) c = p;
        continue;
      }
      if (std::abs(c.depth - p.depth) > config.surfaceTolerance(c.depth)) continue;
      const float wc = 1.0f - c.confidence + kEps;
      const float wp = 1.0f - p.confidence + kEps;
      c.depth = (wc * c.depth + wp * p.depth) / (wc + wp);
      c.confidence = (wc * c.confidence + wp * p.confidence) / (wc + wp);
    }
  }
}

}  // namespace

TemporalDepthFilter::TemporalDepthFilter(TemporalDepthFilterConfig config)
    : config_(config),
      pdf_alpha_(config.pdf_bins, config.alpha_max),
      pdf_depth_diff_(config.pdf_bins, config.depth_diff_max_m) {
  if (config_.levels < 1) throw Error("TemporalDepthFilter: levels (l_max) must be >= 1");
  if (config_.learning_frames < 0) throw Error("TemporalDepthFilter: learning_frames (C) must be >= 0");
}

bool TemporalDepthFilter::learning() const {
  return frame_ < config_.learning_frames || pdf_alpha_.samples() < config_.min_learning_samples ||
         pdf_depth_diff_.samples() < config_.min_learning_samples;
}

void TemporalDepthFilter::resetHistory() {
  previous_color_.release();
  previous_depth_.release();
  previous_mask_.release();
}

cv::Mat TemporalDepthFilter::apply(const DepthFilterInput& in) {
  checkInput(in);
  const int width = in.depth.cols, height = in.depth.rows;
  if (!previous_depth_.empty() && previous_depth_.size() != in.depth.size()) resetHistory();
  const bool has_previous = !previous_depth_.empty();
  const bool learn = learning();

  const cv::Mat measured = supportedDepth(in.depth, in.mask, config_);
  // GetPrePx (line 7) for every foreground pixel: the precursor must lie in the image, on the
  // previous foreground and carry a depth; it is used only on the same surface (within T(z)).
  cv::Mat pre_depth = cv::Mat::zeros(height, width, CV_32FC1);
  cv::Mat alphas = cv::Mat::zeros(height, width, CV_32FC1);
  cv::Mat motion = cv::Mat::zeros(height, width, CV_32FC1);  // d - d_pre where both exist
  cv::Mat motion_weight = cv::Mat::zeros(height, width, CV_32FC1);
  for (int y = 0; has_previous && y < height; ++y) {
    const float* depth = measured.ptr<float>(y);
    const std::uint8_t* mask = in.mask.ptr<std::uint8_t>(y);
    const cv::Vec3b* color = in.color.ptr<cv::Vec3b>(y);
    const cv::Vec2f* flow = in.flow.ptr<cv::Vec2f>(y);
    for (int x = 0; x < width; ++x) {
      if (mask[x] == 0 || !std::isfinite(flow[x][0]) || !std::isfinite(flow[x][1])) continue;
      const int px = static_cast<int>(std::lround(float(x) + flow[x][0]));
      const int py = static_cast<int>(std::lround(float(y) + flow[x][1]));
      if (px < 0 || py < 0 || px >= width || py >= height || previous_mask_.at<std::uint8_t>(py, px) == 0)
        continue;
      const float d_pre = previous_depth_.at<float>(py, px);
      if (!(d_pre > 0.0f)) continue;
      pre_depth.at<float>(y, x) = d_pre;
      alphas.at<float>(y, x) = precursorConfidence(color[x], previous_color_.at<cv::Vec3b>(py, px));
      if (depth[x] > 0.0f && std::abs(depth[x] - d_pre) <= config_.surfaceTolerance(d_pre)) {
        motion.at<float>(y, x) = depth[x] - d_pre;
        motion_weight.at<float>(y, x) = 1.0f;
      }
    }
  }
  // The flow gives only the motion in the image; a visitor walking towards the camera also moves
  // in depth. The local mean of d - d_pre over the same surface is that motion, and adding it to
  // d_pre keeps the recursion from lagging one frame of depth motion behind.
  if (has_previous && config_.motion_window > 1) {
    const cv::Size window(config_.motion_window, config_.motion_window);
    cv::boxFilter(motion, motion, -1, window, cv::Point(-1, -1), false);
    cv::boxFilter(motion_weight, motion_weight, -1, window, cv::Point(-1, -1), false);
  }

  Level base{width, height, std::vector<Pair>(std::size_t(width) * std::size_t(height))};
  cv::Mat output = cv::Mat::zeros(height, width, CV_32FC1);
  for (int y = 0; y < height; ++y) {
    const float* depth = measured.ptr<float>(y);
    const std::uint8_t* mask = in.mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < width; ++x) {
      if (mask[x] == 0) continue;
      const float d = depth[x];
      float d_pre = pre_depth.at<float>(y, x);
      const float weight = motion_weight.at<float>(y, x);
      if (d_pre > 0.0f && weight > 0.0f) d_pre += motion.at<float>(y, x) / weight;
      const bool has_pre = d_pre > 0.0f && d > 0.0f && std::abs(d - d_pre) <= config_.surfaceTolerance(d_pre);
      const float diff = std::abs(d - d_pre);
      const float alpha = alphas.at<float>(y, x);
      if (learn) {  // lines 11-16: learn the PDFs, pass the frame through
        if (has_pre) {
          pdf_depth_diff_.add(diff);
          pdf_alpha_.add(alpha);
        }
        output.at<float>(y, x) = sanitisedDepth(in.depth.at<float>(y, x));  // gamma_i as it came
        continue;
      }
      // A pixel without a measurement gets no pair and is filled by the push from the current
      // frame's neighbours; carrying d_pre instead would freeze a hole at a stale depth
      // (docs/depthfilter.md, "Holes").
      Pair& pair = base.at(x, y);
      if (has_pre) {
        const float p_diff = pdf_depth_diff_.cdf(diff);                        // line 19
        pair = {(1.0f - p_diff) * d + p_diff * d_pre, pdf_alpha_.cdf(alpha)};  // lines 18-21
      } else if (d > 0.0f) {
        pair = {d, 1.0f};  // no usable precursor: the measurement, least confident
      }
    }
  }

  if (!learn) {
    std::vector<Level> pyramid;
    pyramid.push_back(std::move(base));
    for (int l = 1; l < config_.levels; ++l) {
      const Level& child = pyramid.back();
      if (child.width == 1 && child.height == 1) break;
      Level parent{(child.width + 1) / 2, (child.height + 1) / 2, {}};
      parent.pairs.resize(std::size_t(parent.width) * std::size_t(parent.height));
      pull(child, parent, config_);
      pyramid.push_back(std::move(parent));
    }
    for (std::size_t l = pyramid.size() - 1; l > 0; --l) push(pyramid[l], pyramid[l - 1], config_);
    const Level& filtered = pyramid.front();
    for (int y = 0; y < height; ++y) {
      const std::uint8_t* mask = in.mask.ptr<std::uint8_t>(y);
      float* out = output.ptr<float>(y);
      for (int x = 0; x < width; ++x) {
        const float d = filtered.pairs[std::size_t(y) * std::size_t(width) + std::size_t(x)].depth;
        out[x] = mask[x] != 0 && std::isfinite(d) && d > 0.0f ? d : 0.0f;
        // A hole next to a depth edge could belong to either surface; a fill from the wrong one
        // flickers between them from frame to frame, so it stays a hole.
        if (out[x] > 0.0f && measured.at<float>(y, x) <= 0.0f && nearDepthEdge(measured, x, y, config_))
          out[x] = 0.0f;
      }
    }
  }

  previous_color_ = in.color.clone();
  previous_depth_ = output.clone();
  previous_mask_ = in.mask.clone();
  ++frame_;
  return output;
}

}  // namespace holo::depthfilter
