// Calibration boards: a plain chessboard or a ChArUco board, parsed from a one-line spec, found
// in images with OpenCV (calib3d / aruco), drawn for the technician, and rendered as a flat
// texture for synthetic tests and the simulated wizard run.
//
// Board frame: origin at the board's first inner corner (chessboard) or at its outer corner
// (ChArUco, OpenCV's convention), X along the columns, Y along the rows, Z = 0 on the board
// (the printed side faces -Z). Units: metres.
#pragma once

#include <opencv2/aruco/charuco.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace holo::calib {

struct BoardSpec {
  enum class Kind { Chessboard, Charuco };
  Kind kind = Kind::Chessboard;
  // Chessboard: inner corners per row (cols) and per column (rows), as cv::findChessboardCorners.
  // ChArUco: squares in X (cols) and Y (rows), as cv::aruco::CharucoBoard::create.
  int cols = 0;
  int rows = 0;
  double square_m = 0.0;
  double marker_m = 0.0;   // ChArUco only: marker side, < square_m
  std::string dictionary;  // ChArUco only: OpenCV predefined dictionary, e.g. "DICT_5X5_100"

  // "chessboard:COLSxROWS:SQUARE_M" or "charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT" (DICT with or
  // without its "DICT_" prefix). Throws InputError naming `source` (a flag or file) and what is wrong.
  static BoardSpec parse(const std::string& text, const std::string& source = "--board");
  std::string describe() const;

  // Board-frame positions of every corner the board can yield, indexed by corner id (chessboard:
  // row-major inner corners; ChArUco: OpenCV's chessboard corner ids).
  std::vector<cv::Point3f> allCorners() const;
  cv::Ptr<cv::aruco::CharucoBoard> charucoBoard() const;  // ChArUco only
  // The board's printed extent in the board frame (metres): [min corner, max corner] in X and Y.
  cv::Rect2d extent() const;
};

// Corners found in one image, with their ids and board-frame positions (same order).
struct BoardDetection {
  std::vector<cv::Point2f> image_points;
  std::vector<cv::Point3f> object_points;
  std::vector<int> ids;
  int markers = 0;  // ChArUco: markers found (diagnostics)
  bool usable() const { return image_points.size() >= 6; }
  // Width of the detected corners' bounding box as a share of the image width (0 when empty).
  double widthFraction(int image_width) const;
};

// Finds the board's corners (sub-pixel refined). An image without the board gives an empty
// detection, never an error. Accepts 8-bit grey or BGR.
BoardDetection detectBoard(const BoardSpec& board, const cv::Mat& image);

// Draws the detected corners (and ids for ChArUco) onto a BGR copy of `image`.
cv::Mat drawDetection(const BoardSpec& board, const cv::Mat& image, const BoardDetection& detection);

// A flat, fronto-parallel picture of the board (white margin, CV_8UC1) and the homography that
// maps board-frame metres (X, Y, 1) to its pixels. `pixels_per_square` sets the resolution.
struct BoardTexture {
  cv::Mat image;
  cv::Matx33d board_to_pixel;
};
BoardTexture renderBoardTexture(const BoardSpec& board, int pixels_per_square = 80);

// A grey-level contact sheet of several images with their detections drawn (for the PNG the
// intrinsics command writes): `columns` thumbnails per row, each `thumb_width` pixels wide.
cv::Mat detectionContactSheet(const std::vector<cv::Mat>& drawn, int columns = 4, int thumb_width = 320);

}  // namespace holo::calib
