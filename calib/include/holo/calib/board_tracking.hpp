// The board followed through a camera's frames as a technician moves it: the board found in every
// frame, how far its corners moved since the previous frame (steady or moving), how the view sits
// in the picture (where, how large, how tilted), and for intrinsics whether a frame adds a view
// unlike the ones already kept. Steps after the intrinsics (poses, and the depth-to-colour and
// colour-gain steps) reuse the same per-frame observations: corners with their ids and, once the
// camera's intrinsics are known, the board's pose in the camera frame.
//
// Units: image pixels; board and pose in metres (board frame as in board.hpp); angles in degrees.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "holo/calib/board.hpp"
#include "holo/calib/intrinsics.hpp"
#include "holo/core/camera_model.hpp"
#include "holo/core/rgbd_frame.hpp"

namespace holo::calib {

// A frame counts as steady when the corners it shares with the previous frame moved less than
// this on average: a board held still by hand jitters by a few tenths of a pixel, one in motion
// moves several pixels per frame and is blurred.
inline constexpr double kSteadyMotionPx = 1.0;

// How a view of the board sits in the picture. Tilt comes from the board-to-image homography's
// foreshortening (the ratio of its singular values at the board's centre), so it needs no
// intrinsics; the tilt direction is the side of the picture where the board is further away.
struct ViewPose {
  cv::Point2d centre;         // centroid of the detected corners, as a fraction of width and height
  double width_fraction = 0;  // the corners' bounding box width over the image width
  double tilt_deg = 0;        // angle between the board's normal and the line of sight
  enum Direction { Frontal = 0, Right, Down, Left, Up };
  Direction direction = Frontal;  // Frontal when tilt_deg < kFrontalTiltDeg
};
inline constexpr double kFrontalTiltDeg = 15.0;
// Needs a usable detection.
ViewPose describeView(const BoardDetection& detection, cv::Size image);
const char* toString(ViewPose::Direction direction);

// One camera's observation of the board in one frame.
struct BoardFrameObservation {
  int camera = 0;
  std::int64_t frame = 0;      // index of the frame among those the step took from this camera
  Nanoseconds device_time{0};  // the frame's timestamp (pairing with depth or other cameras)
  BoardDetection detection;    // corners (image px), their ids and board-frame positions
  double motion_px = -1.0;     // mean corner motion since the previous frame; -1 = not comparable
  bool steady = false;         // motion_px < kSteadyMotionPx (always true for stills)
  bool kept = false;           // the step used this frame
  std::optional<cv::Matx44d> T_camera_board;  // board -> camera (metres), when intrinsics are known
};

// Board -> camera pose from a usable detection and known intrinsics (solvePnP, iterative).
std::optional<cv::Matx44d> boardPose(const BoardDetection& detection, const Intrinsics& intrinsics);

// Which parts of the picture and which tilts the kept views cover: a 3x3 grid of the image (by the
// board's centroid) and five tilt classes (frontal; further away to the right, bottom, left, top).
struct CoverageGrid {
  static constexpr int kCells = 3;
  std::array<int, kCells * kCells> image{};  // kept views per cell, row-major
  std::array<int, 5> tilt{};                 // kept views per ViewPose::Direction
  void add(const ViewPose& view);
  int imageCellsFilled() const;
  int tiltClassesFilled() const;
  // "image 7/9 cells, tilt 4/5 (frontal right left up)"
  std::string describe() const;
  // Draws the grid on `picture` (BGR): filled cells green, empty ones outlined, and the tilt
  // classes as five boxes along the bottom edge.
  void draw(cv::Mat& picture) const;
};

// Chooses, frame by frame, the views of one camera that intrinsics are computed from: a frame is
// kept when the board is found, steady, and not a near copy of a kept view (its centre, size or
// tilt differ enough), so holding the board still in one place yields one view, not hundreds.
class IntrinsicsViewSelector {
 public:
  IntrinsicsViewSelector(BoardSpec board, int camera, cv::Size image_size, bool stills);
  // Detects the board in `frame.colour` and decides whether to keep the frame.
  const BoardFrameObservation& add(const RgbdFrame& frame, const std::string& name);

  const std::vector<BoardView>& keptViews() const { return kept_; }
  const std::vector<cv::Mat>& keptPictures() const { return kept_pictures_; }  // detections drawn
  const std::vector<BoardFrameObservation>& observations() const { return observations_; }
  const CoverageGrid& coverage() const { return coverage_; }
  int framesWithBoard() const { return frames_with_board_; }
  int framesMoving() const { return frames_moving_; }
  int framesRepeated() const { return frames_repeated_; }  // steady, but like a kept view

 private:
  bool nearCopy(const ViewPose& view) const;

  BoardSpec board_;
  int camera_;
  cv::Size image_size_;
  bool stills_;
  std::vector<BoardFrameObservation> observations_;
  std::vector<BoardView> kept_;
  std::vector<cv::Mat> kept_pictures_;
  std::vector<ViewPose> kept_poses_;
  CoverageGrid coverage_;
  int frames_with_board_ = 0;
  int frames_moving_ = 0;
  int frames_repeated_ = 0;
};

// Mean displacement (px) of the corners two detections share; -1 with fewer than 4 shared.
double cornerMotion(const BoardDetection& previous, const BoardDetection& current);

}  // namespace holo::calib
