// Display alignment of the four pyramid faces: the similarity (plus optional mirror) that maps a
// face view onto its part of the monitor, a test pattern to show, and the fit of that transform
// from where the pattern's dots were seen (clicked by the technician or found by a camera).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "holo/calib/calibration_io.hpp"

namespace holo::calib {

// View pixel p -> screen pixel c + offset + R(rotation) * scale * M * (p - c), with c the view's
// centre ((w-1)/2, (h-1)/2), M = diag(-1, 1) when mirrored, R counter-clockwise on screen (y down).
cv::Matx23d faceTransform(const FaceAlignment& alignment, cv::Size view);

// The test pattern: a white frame, a 5x5 grid of dots (the fit's reference points), an arrow
// pointing up and the face number drawn so mirroring and rotation are obvious. CV_8UC3.
cv::Mat drawTestPattern(cv::Size view, int face);
std::vector<cv::Point2f> testPatternDots(cv::Size view);

struct FaceFit {
  FaceAlignment alignment;
  double residual_px = 0.0;  // RMS distance of the observed dots from the fitted transform
};

// Fits the alignment that takes `pattern` dots to `observed` ones (same order, at least 3).
// Tries both with and without the mirror and keeps the better. Throws InputError (naming
// `source`) with too few or non-finite points.
FaceFit estimateFaceAlignment(const std::vector<cv::Point2f>& pattern,
                              const std::vector<cv::Point2f>& observed, cv::Size view,
                              const std::string& source = "display alignment");

}  // namespace holo::calib
