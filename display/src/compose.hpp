// What both presenters share (private): checking the faces, choosing crops, drawing one output.
#pragma once

#include <array>

#include "holo/display/quad_view_presenter.hpp"
#include "quad_renderer.hpp"

namespace holo::display {

// Checks the faces' types and returns each face's crop (auto-fit or the whole image); an empty
// face keeps its crop from `previous` (its texture keeps the last image), so it is drawn again.
std::array<cv::Rect2f, kFaceCount> chooseCrops(const DisplayConfig& config, const FaceImages& faces,
                                               const FaceImages* coverage,
                                               const std::array<cv::Rect2f, kFaceCount>& previous);

// Clears output `output` (at `origin` in a framebuffer `framebuffer_height` tall) to black and
// draws the faces that belong to it, already uploaded to `renderer`.
void drawOutput(QuadRenderer& renderer, const DisplayConfig& config, int output, cv::Point origin,
                cv::Size size, int framebuffer_height, const std::array<cv::Rect2f, kFaceCount>& crops);

}  // namespace holo::display
