#include "holo/core/rgbd_frame.hpp"

#include <string>

#include "holo/core/error.hpp"

namespace holo {

void RgbdFrame::validate() const {
  const std::string who = "frame " + std::to_string(sequence) + " of camera " + std::to_string(camera_id);
  if (camera_id < 0) throw Error(who + ": camera id must be >= 0");
  if (!colour.empty() && colour.type() != CV_8UC3) throw Error(who + ": colour must be CV_8UC3 (BGR)");
  if (!depth.empty() && depth.type() != CV_32FC1) throw Error(who + ": depth must be CV_32FC1 metres");
  if (!colour.empty() && !depth.empty() && colour.size() != depth.size())
    throw Error(who + ": colour and depth sizes differ");
}

}  // namespace holo
