#include "holo/calib/colour_gains.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::calib {

namespace {

// A white sample this bright in some channel may be clipped: its true level is unknown.
constexpr int kClippedLevel = 254;
constexpr float kMaxClippedFraction = 0.05f;

const std::array<float, 256>& linearTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i)
      t[static_cast<std::size_t>(i)] = srgbToLinear(static_cast<float>(i) / 255.0f);
    return t;
  }();
  return table;
}

// Where to sample a square, in its own coordinates (u, v) in [0, 1]^2 between its four corners.
// A chessboard square is uniform: its middle, away from the blurred edges. A ChArUco white
// square holds a marker, so both colours are sampled on the ring halfway across the margin
// between the marker and the square's edge.
std::vector<cv::Point2f> samplePattern(const BoardSpec& board) {
  std::vector<cv::Point2f> uv;
  if (board.kind == BoardSpec::Kind::Chessboard) {
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        uv.emplace_back(0.3f + 0.1f * static_cast<float>(i), 0.3f + 0.1f * static_cast<float>(j));
    return uv;
  }
  const float margin = static_cast<float>((board.square_m - board.marker_m) / 4.0 / board.square_m);
  for (int k = 0; k < 5; ++k) {
    const float t = 0.3f + 0.1f * static_cast<float>(k);
    uv.emplace_back(t, margin);
    uv.emplace_back(t, 1.0f - margin);
    uv.emplace_back(margin, t);
    uv.emplace_back(1.0f - margin, t);
  }
  return uv;
}

struct SquareSample {
  vec3 level{0.0f};  // trimmed mean, linear RGB
  float luminance = 0.0f;
  int clipped = 0;
  int samples = 0;
};

}  // namespace

BoardSquareLevels measureBoardSquares(const BoardSpec& board, const cv::Mat& bgr,
                                      const BoardDetection& detection, const std::string& source) {
  if (bgr.type() != CV_8UC3) throw InputError(source, "colour", "an 8-bit BGR picture");
  // Grid position of every detected corner from its board-frame position.
  const std::vector<cv::Point3f> all = board.allCorners();
  float x0 = all.front().x, y0 = all.front().y;
  for (const auto& p : all) {
    x0 = std::min(x0, p.x);
    y0 = std::min(y0, p.y);
  }
  const float square = static_cast<float>(board.square_m);
  std::map<std::pair<int, int>, cv::Point2f> corner;  // (row, col) -> image point
  for (std::size_t i = 0; i < detection.image_points.size(); ++i) {
    const cv::Point3f& p = detection.object_points[i];
    corner[{static_cast<int>(std::lround((p.y - y0) / square)),
            static_cast<int>(std::lround((p.x - x0) / square))}] = detection.image_points[i];
  }
  const std::vector<cv::Point2f> pattern = samplePattern(board);
  const auto& linear = linearTable();
  // The squares of the two parities: one set is white, the other black.
  std::array<std::vector<SquareSample>, 2> parity;
  for (const auto& [rc, p00] : corner) {
    const auto p01 = corner.find({rc.first, rc.second + 1});
    const auto p10 = corner.find({rc.first + 1, rc.second});
    const auto p11 = corner.find({rc.first + 1, rc.second + 1});
    if (p01 == corner.end() || p10 == corner.end() || p11 == corner.end()) continue;
    std::array<std::vector<float>, 3> channel;
    SquareSample s;
    for (const cv::Point2f& uv : pattern) {
      // Bilinear between the four corners: a square is small enough for lens distortion to
      // bend it by a fraction of a pixel.
      const cv::Point2f q = (1 - uv.x) * (1 - uv.y) * p00 + uv.x * (1 - uv.y) * p01->second +
                            (1 - uv.x) * uv.y * p10->second + uv.x * uv.y * p11->second;
      const int x = static_cast<int>(std::lround(q.x)), y = static_cast<int>(std::lround(q.y));
      if (x < 0 || y < 0 || x >= bgr.cols || y >= bgr.rows) continue;
      const cv::Vec3b v = bgr.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) channel[static_cast<std::size_t>(c)].push_back(linear[v[2 - c]]);
      if (std::max({v[0], v[1], v[2]}) >= kClippedLevel) ++s.clipped;
      ++s.samples;
    }
    if (s.samples < static_cast<int>(pattern.size()) / 2) continue;
    // A trimmed mean, not a median: robust to a stray pixel, and the sensor's noise dithers the
    // 8-bit steps so the mean resolves levels between them (a median stays on a step, up to 0.6%
    // off at the white squares' levels).
    for (int c = 0; c < 3; ++c) {
      auto& values = channel[static_cast<std::size_t>(c)];
      std::sort(values.begin(), values.end());
      const std::size_t trim = values.size() / 5;
      double sum = 0.0;
      for (std::size_t k = trim; k < values.size() - trim; ++k) sum += values[k];
      s.level[c] = static_cast<float>(sum / static_cast<double>(values.size() - 2 * trim));
    }
    s.luminance = (s.level.r + s.level.g + s.level.b) / 3.0f;
    parity[static_cast<std::size_t>((rc.first + rc.second) % 2)].push_back(s);
  }
  auto mean = [](const std::vector<SquareSample>& squares) {
    vec3 sum(0.0f);
    float luminance = 0.0f;
    for (const auto& s : squares) {
      sum += s.level;
      luminance += s.luminance;
    }
    const float n = static_cast<float>(std::max<std::size_t>(1, squares.size()));
    return std::make_pair(sum / n, luminance / n);
  };
  const auto [mean0, lum0] = mean(parity[0]);
  const auto [mean1, lum1] = mean(parity[1]);
  const std::size_t white = lum0 >= lum1 ? 0 : 1;
  BoardSquareLevels levels;
  levels.white = white == 0 ? mean0 : mean1;
  levels.black = white == 0 ? mean1 : mean0;
  levels.white_squares = static_cast<int>(parity[white].size());
  levels.black_squares = static_cast<int>(parity[1 - white].size());
  if (levels.white_squares < 2 || levels.black_squares < 2)
    throw InputError(
        source, "board squares", "at least 2 white and 2 black squares with their four corners seen",
        std::to_string(levels.white_squares) + " white, " + std::to_string(levels.black_squares) +
            " black (hint: show the whole board to the camera)");
  int clipped = 0, samples = 0;
  for (const auto& s : parity[white]) {
    clipped += s.clipped;
    samples += s.samples;
  }
  levels.clipped_fraction = static_cast<float>(clipped) / static_cast<float>(std::max(1, samples));
  if (levels.clipped_fraction > kMaxClippedFraction)
    throw InputError(source, "white squares", "unclipped white squares (at most 5% of samples at 254-255)",
                     std::to_string(static_cast<int>(std::lround(levels.clipped_fraction * 100.0f))) +
                         "% clipped (hint: lower the camera's exposure or gain, or the light on the board)");
  for (int c = 0; c < 3; ++c)
    if (!(levels.white[c] > levels.black[c] * 1.5f + 1e-3f))
      throw InputError(
          source, "board squares", "white squares clearly brighter than black ones in every channel",
          "channel " + std::to_string(c) + ": white " + std::to_string(levels.white[c]) + ", black " +
              std::to_string(levels.black[c]) + " (hint: light the board evenly, avoid glare)");
  return levels;
}

vec3 colourGainsFor(const BoardSquareLevels& levels, float target) {
  return vec3(target) / (levels.white - levels.black);
}

std::vector<vec3> matchCameraColours(const std::vector<BoardSquareLevels>& levels) {
  float target = 0.0f;
  for (const auto& l : levels) {
    const vec3 contrast = l.white - l.black;
    target += (contrast.r + contrast.g + contrast.b) / 3.0f;
  }
  target /= static_cast<float>(std::max<std::size_t>(1, levels.size()));
  std::vector<vec3> gains;
  for (const auto& l : levels) gains.push_back(colourGainsFor(l, target));
  return gains;
}

cv::Mat applyColourGains(const cv::Mat& bgr, vec3 gains) {
  HOLO_ASSERT(bgr.type() == CV_8UC3);
  const auto& linear = linearTable();
  std::array<std::array<std::uint8_t, 256>, 3> table{};
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 256; ++i)
      table[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(
          std::lround(255.0f * linearToSrgb(linear[static_cast<std::size_t>(i)] * gains[2 - c])));
  cv::Mat out(bgr.size(), CV_8UC3);
  for (int y = 0; y < bgr.rows; ++y) {
    const cv::Vec3b* in = bgr.ptr<cv::Vec3b>(y);
    cv::Vec3b* o = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; ++x)
      for (int c = 0; c < 3; ++c) o[x][c] = table[static_cast<std::size_t>(c)][in[x][c]];
  }
  return out;
}

}  // namespace holo::calib
