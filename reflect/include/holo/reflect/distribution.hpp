// Piecewise-constant distributions over a grid of non-negative weights, for importance sampling.
// Sums are kept in double so a single weight of 1e6 among zeros, or a sun 1e5 above the sky,
// samples exactly in proportion. An all-zero (or empty) grid is valid: it samples nothing
// (sample() reports probability 0) and every probability is 0.
#pragma once

#include <vector>

#include "holo/core/math.hpp"

namespace holo::reflect {

class Distribution2D {
 public:
  Distribution2D() = default;
  // weights: row-major, width * height values >= 0 (NaN/Inf/negative count as 0).
  Distribution2D(const std::vector<double>& weights, int width, int height);

  struct Sample {
    int x = 0, y = 0;        // chosen cell
    double probability = 0;  // discrete probability of that cell (0 when the grid is empty)
    vec2 within{0.5f};       // u remapped to [0,1)^2 inside the cell, for continuous warps
  };
  Sample sample(const vec2& u) const;
  double probability(int x, int y) const;  // discrete probability of a cell
  double total() const { return total_; }  // sum of the weights
  bool empty() const { return !(total_ > 0); }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_ = 0, height_ = 0;
  double total_ = 0;
  std::vector<double> weights_;  // cleaned weights
  std::vector<double> row_cdf_;  // height + 1 entries, normalised
  std::vector<double> row_sums_;
  std::vector<double> column_cdfs_;  // per row, width + 1 entries, normalised
};

}  // namespace holo::reflect
