// The verification jig: what each camera sees of the pyramid base for the wizard's last check.
// The cameras sit on the base's sides and look outward, so none of them sees the base itself.
// The jig is a stiff arm that slots onto the base's side at the two dowel pins beside the camera
// (so its pose in the pyramid frame is fixed by the base's machining, not by where a technician
// stood a board) and holds a flat plate upright 0.45 m in front of the camera, facing it: a mid
// grey plate with a printed white square and a black square inside it. The printed squares' edges
// are the known geometry the alignment figure (edge_alignment.hpp) projects through the camera's
// calibration. Units: metres; target frame: origin at the plate's top-left corner, +X along the
// top edge, +Y down, +Z away from the camera (the printed side faces -Z, as a board's does).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "holo/calib/board.hpp"
#include "holo/calib/edge_alignment.hpp"

namespace holo::calib {

inline constexpr double kVerificationPlateSize = 0.5;     // the plate's side
inline constexpr double kVerificationWhiteSquare = 0.36;  // centred on the plate
inline constexpr double kVerificationBlackSquare = 0.18;  // centred inside the white square
inline constexpr double kVerificationDistance = 0.45;     // plate centre in front of the base's side

// T_world_target of the jig on the side of camera `camera` of a base `base_half_width` wide
// (camera f faces azimuth f * 90 degrees, as the marked easel spots do): upright, 0.08 m below
// the base top, turned 15 degrees and leaned back 10 degrees so that its perspective pins down
// the camera's distance and direction apart.
cv::Matx44d verificationTargetPose(int camera, double base_half_width = 0.3);

// The printed squares' eight edges in the world frame, for the target at T_world_target.
std::vector<EdgeSegment> verificationTargetEdges(const cv::Matx44d& T_world_target);

// The plate as printed (grey levels: plate 96, white 235, black 20), `pixels_per_metre` fine.
BoardTexture renderVerificationTargetTexture(int pixels_per_metre = 1000);

}  // namespace holo::calib
