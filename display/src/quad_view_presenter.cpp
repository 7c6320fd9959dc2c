#include "holo/display/quad_view_presenter.hpp"

#include <algorithm>

namespace holo::display {

int screenFaceViewPixels(const QuadViewPresenter& presenter) {
  const DisplayConfig& config = presenter.config();
  int side = 1;
  for (int output = 0; output < outputCount(config.layout); ++output)
    side = std::max(side, faceViewPixels(config, presenter.outputSize(output)));
  return side;
}

}  // namespace holo::display
