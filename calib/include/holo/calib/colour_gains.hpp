// Colour matching of the cameras from the calibration board: every camera sees the board's
// white and black squares, which are neutral (the same reflectance in red, green and blue) and
// the same for every camera, so the difference of their linear colours measures each camera's
// per-channel response (white balance and exposure together). The gains that bring every camera
// to a common response make a grey surface seen by all four cameras the same linear colour.
//
// Model: linear(observed)_c = k_c * radiance_c + o_c per channel c, with o_c an offset (stray
// light, black level) the same on white and black squares; the black squares cancel it, so the
// gain is g_c = target / (white_c - black_c). Gains multiply linear colour (after sRGB decoding,
// before the exposure division); 1 is no correction. Colours here are linear RGB (not BGR).
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "holo/calib/board.hpp"
#include "holo/core/math.hpp"

namespace holo::calib {

// Mean linear RGB of the board's white and of its black squares in one picture.
struct BoardSquareLevels {
  vec3 white{0.0f};
  vec3 black{0.0f};
  int white_squares = 0;  // squares sampled of each colour
  int black_squares = 0;
  float clipped_fraction = 0.0f;  // share of white samples at 254 or 255 in some channel
};

// Samples the squares whose four corners `detection` found (the inner part of each square: a
// chessboard square's middle, a ChArUco square's white margin around its marker). `bgr` is the
// 8-bit sRGB picture the detection came from. Throws InputError (naming `source`) when fewer
// than 2 squares of each colour were seen, when white is not brighter than black in every
// channel, or when more than 5% of the white samples are clipped (the hint says to lower the
// exposure).
BoardSquareLevels measureBoardSquares(const BoardSpec& board, const cv::Mat& bgr,
                                      const BoardDetection& detection, const std::string& source);

// Per-channel gains (linear RGB) that give each camera the white-minus-black contrast `target`.
vec3 colourGainsFor(const BoardSquareLevels& levels, float target);

// Gains for several cameras at once: the common target is the mean white-minus-black contrast
// over cameras and channels, so the correction keeps the installation's overall brightness.
std::vector<vec3> matchCameraColours(const std::vector<BoardSquareLevels>& levels);

// Applies `gains` (linear RGB) to an 8-bit sRGB BGR picture (tests and previews).
cv::Mat applyColourGains(const cv::Mat& bgr, vec3 gains);

}  // namespace holo::calib
