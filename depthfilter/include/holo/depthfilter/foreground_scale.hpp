// The foreground's resolution: the per-camera step (mask, flow, persistence, filter, border,
// back-projection) may run on frames reduced by an integer `scale` (1: the camera's own
// resolution; 2: half width and height, a quarter of the pixels). The foreground feeds voxels a
// few centimetres wide, several camera pixels each, so it needs less than the camera's resolution.
//
// Reduction: colour by the block's area average; depth by one reading of each block (its top-left
// pixel), never an average, so a block across a depth edge gives a depth the sensor read, not a
// flying point between the two surfaces. The reduced camera sees the same rays: a reduced pixel u
// is the block of full pixels scale*u .. scale*u + scale - 1, whose centre is
// scale*u + (scale - 1) / 2 in the camera's pixel coordinates (pixel centres at integers).
// Back to full size: each reduced pixel's value repeated over its block (nearest), so a pixel the
// reduced foreground leaves out is left out over its whole block.
// Invariant: the full size is a multiple of `scale` (checked where a pipeline is made).
#pragma once

#include "holo/core/camera_model.hpp"
#include "holo/core/rgbd_frame.hpp"

namespace holo::depthfilter {

inline constexpr int kMaxForegroundScale = 2;
// The product's: what ForegroundPipelineConfig, the `depthfilter:` section and `eval depth` take
// when nothing is given (docs/depthfilter.md "Speed" has the figures it was chosen by).
inline constexpr int kDefaultForegroundScale = 1;

// Throws holo::Error unless scale is in [1, kMaxForegroundScale] and divides width and height.
void checkForegroundScale(int scale, int width, int height);
// The camera as the reduced frames see it (intrinsics divided, distortion and pose unchanged).
CameraModel reducedCamera(const CameraModel& camera, int scale);
// The frame at the reduced size (colour area average, depth the block's top-left reading), its
// camera id, sequence and times kept. scale 1 returns the frame itself (shared images).
RgbdFrame reducedFrame(const RgbdFrame& frame, int scale);
// Each reduced pixel repeated over its block of `full` size (any type); `full` is the reduced size
// times the scale.
cv::Mat expandedToFull(const cv::Mat& reduced, cv::Size full);

}  // namespace holo::depthfilter
