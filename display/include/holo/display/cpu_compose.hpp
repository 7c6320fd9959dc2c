// The quad view composed on the CPU: the reference the OpenGL presenters are tested against, and
// a way to see a layout without any OpenGL at all. It follows the GPU path's rules exactly:
//  * a face covers an output pixel when the pixel's centre lies inside the face's transformed
//    quad (FacePlacement, layout.hpp); faces are drawn in order 0..3, later ones on top;
//  * the colour is the face image sampled bilinearly at that centre with clamp-to-edge, as
//    OpenGL's GL_LINEAR does (texel k's centre at k + 0.5);
//  * linear HDR faces (CV_32FC3) are repaired before sampling (NaN -> 0, +Inf -> FLT_MAX so it
//    saturates, negatives -> 0: bilinear filtering would otherwise spread a NaN to its
//    neighbours), multiplied by config.exposure, clamped to [0, 1] and sRGB-encoded; 8-bit faces
//    are already sRGB;
//  * everything else is black (0, 0, 0).
// On OpenGL the result agrees within 1 LSB where no pixel centre lies exactly on a quad's edge
// (there OpenGL's tie rule decides) and where the bilinear weights are multiples of 1/32.
#pragma once

#include <array>
#include <opencv2/core.hpp>

#include "holo/display/layout.hpp"

namespace holo::display {

// The headless canvas (canvasSize(config), CV_8UC3 BGR) showing `faces` with the crop
// rectangles `crops` (face image pixels; an empty face or crop is not drawn).
cv::Mat composeCanvasCpu(const DisplayConfig& config, const std::array<cv::Mat, kFaceCount>& faces,
                         const std::array<cv::Rect2f, kFaceCount>& crops);

// CV_8UC1 mask of the canvas pixels some face covers (255) under the same rule.
cv::Mat coverageCpu(const DisplayConfig& config, const std::array<cv::Mat, kFaceCount>& faces,
                    const std::array<cv::Rect2f, kFaceCount>& crops);

}  // namespace holo::display
