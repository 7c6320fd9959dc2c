#include "holo/eval/reflection_flicker.hpp"

#include <algorithm>
#include <cmath>

#include "holo/core/error.hpp"
#include "table_number.hpp"

namespace holo::eval {
namespace {

void checkFrame(const DisplayedFrame& frame, const DisplayedFrame& truth) {
  if (frame.display.size() != truth.display.size() || frame.weight.size() != truth.display.size())
    throw Error("ReflectionFlickerScorer: the method and the truth need the same views");
  for (std::size_t v = 0; v < truth.display.size(); ++v) {
    const cv::Size size = truth.display[v].size();
    if (truth.display[v].type() != CV_8UC3 || frame.display[v].type() != CV_8UC3 ||
        truth.weight[v].type() != CV_32FC1 || frame.weight[v].type() != CV_32FC1 ||
        frame.display[v].size() != size || truth.weight[v].size() != size || frame.weight[v].size() != size)
      throw Error(
          "ReflectionFlickerScorer: each view needs a CV_8UC3 display and a CV_32FC1 weight of one size");
  }
}

// Mean over the channels of the squared difference of two BGR level triples.
double squared(float b, float g, float r) {
  return (double(b) * b + double(g) * g + double(r) * r) / 3.0;
}

}  // namespace

void ReflectionFlickerScorer::add(const DisplayedFrame& method, const DisplayedFrame& truth) {
  checkFrame(method, truth);
  for (std::size_t v = 0; v < truth.weight.size(); ++v)
    for (int y = 0; y < truth.weight[v].rows; ++y) {
      const float* wt = truth.weight[v].ptr<float>(y);
      const float* wm = method.weight[v].ptr<float>(y);
      for (int x = 0; x < truth.weight[v].cols; ++x) {
        truth_weight_ += wt[x];
        missing_weight_ += std::max(0.0f, wt[x] - wm[x]);
      }
    }
  if (!previous_truth_.display.empty()) {
    if (previous_truth_.display.size() != truth.display.size() ||
        previous_truth_.display[0].size() != truth.display[0].size())
      throw Error("ReflectionFlickerScorer: consecutive frames need the same views");
    Pair pair;
    for (std::size_t v = 0; v < truth.display.size(); ++v)
      for (int y = 0; y < truth.display[v].rows; ++y) {
        const cv::Vec3b* dm = method.display[v].ptr<cv::Vec3b>(y);
        const cv::Vec3b* dt = truth.display[v].ptr<cv::Vec3b>(y);
        const cv::Vec3b* pm = previous_method_.display[v].ptr<cv::Vec3b>(y);
        const cv::Vec3b* pt = previous_truth_.display[v].ptr<cv::Vec3b>(y);
        const float* wm = method.weight[v].ptr<float>(y);
        const float* wt = truth.weight[v].ptr<float>(y);
        const float* qm = previous_method_.weight[v].ptr<float>(y);
        const float* qt = previous_truth_.weight[v].ptr<float>(y);
        for (int x = 0; x < truth.display[v].cols; ++x) {
          const bool truth_shows = wt[x] > 0.0f || qt[x] > 0.0f;
          if (!truth_shows && !(wm[x] > 0.0f || qm[x] > 0.0f)) continue;
          pair.truth_pixels += truth_shows;
          float error[3], error_change[3], change[3];
          for (int c = 0; c < 3; ++c) {
            error[c] = float(dm[x][c]) - float(dt[x][c]);
            const float previous_error = float(pm[x][c]) - float(pt[x][c]);
            error_change[c] = error[c] - previous_error;
            change[c] = float(dm[x][c]) - float(pm[x][c]);
          }
          pair.temporal += squared(error_change[0], error_change[1], error_change[2]);
          pair.missing += double(std::max(0.0f, wt[x] - wm[x])) * squared(error[0], error[1], error[2]);
          pair.change += squared(change[0], change[1], change[2]);
        }
      }
    pairs_.push_back(pair);
  }
  previous_method_ = {{}, {}};
  previous_truth_ = {{}, {}};
  for (std::size_t v = 0; v < truth.display.size(); ++v) {
    previous_method_.display.push_back(method.display[v].clone());
    previous_method_.weight.push_back(method.weight[v].clone());
    previous_truth_.display.push_back(truth.display[v].clone());
    previous_truth_.weight.push_back(truth.weight[v].clone());
  }
}

ReflectionFlickerMetrics ReflectionFlickerScorer::metrics() const {
  ReflectionFlickerMetrics m;
  double flicker = 0.0, temporal = 0.0, missing = 0.0, change = 0.0;
  for (const Pair& p : pairs_) {
    if (p.truth_pixels == 0) {
      m.per_pair.push_back(ReflectionFlickerMetrics::kNaN);
      continue;
    }
    const double n = double(p.truth_pixels);
    m.per_pair.push_back((p.temporal + p.missing) / n);
    flicker += m.per_pair.back();
    temporal += p.temporal / n;
    missing += p.missing / n;
    change += p.change / n;
    ++m.scored_pairs;
  }
  if (m.scored_pairs > 0) {
    const double n = double(m.scored_pairs);
    m.flicker = flicker / n;
    m.temporal = temporal / n;
    m.missing = missing / n;
    m.displayed_change = change / n;
  }
  if (truth_weight_ > 0.0) m.missing_share = missing_weight_ / truth_weight_;
  return m;
}

std::string reflectionFlickerTable(std::span<const std::pair<std::string, ReflectionFlickerMetrics>> rows) {
  std::string table =
      "| fed to the renderer | flicker (levels^2) | temporal | missing | missing share | displayed change |\n"
      "|---|---|---|---|---|---|\n";
  for (const auto& [name, m] : rows)
    table += "| " + name + " | " + tableNumber(m.flicker, "%.2f") + " | " + tableNumber(m.temporal, "%.2f") +
             " | " + tableNumber(m.missing, "%.2f") + " | " + tableNumber(m.missing_share, "%.3f") + " | " +
             tableNumber(m.displayed_change, "%.2f") + " |\n";
  return table;
}

}  // namespace holo::eval
