// The AR check view of one of an installation's cameras (ar/ar_view.hpp, ar/live_composite.hpp):
// frames grabbed from the camera (a rig camera's depth corrected like the frame loop's: the
// fitted depth scale, the reprojection of a second device's depth into the colour image), the
// camera refused with an InputError naming it and what is needed (ar::requireArCameraIndex,
// ar::requireArCameraInputs), the relic of the installation composited over each frame with its
// shadow and light. AR camera indices: the rig's cameras 0..cameras.size()-1, then the
// installation's check cameras (installation.hpp). Units: metres, world (pyramid) frame.
#pragma once

#include <memory>
#include <optional>

#include "holo/ar/ar_view.hpp"
#include "holo/ar/live_composite.hpp"
#include "holo/pipeline/installation.hpp"

namespace holo::pipeline {

// The cameras the AR check view can be made for: the rig's and the check cameras.
int arCameraCount(const Installation& installation);

// Grabs one frame of camera `index` (waiting up to `timeout_s` seconds for it) and renders its
// composite. `settings.exposure` and `settings.panorama_yaw_rad` are the installation's.
ar::ArView arCheckView(Installation& installation, int index, ar::ArViewSettings settings,
                       double timeout_s = 10.0);

// The live AR check view of camera `index`: each step() grabs the camera's next frame and adds
// it to the composite refined while still (ar::LiveComposite). The camera index is refused on
// construction, the frame's inputs on the first step(). `settings.view.exposure` and
// `settings.view.panorama_yaw_rad` are the installation's. The installation must outlive it.
class ArLiveView {
 public:
  ArLiveView(Installation& installation, int index, ar::LiveCompositeSettings settings,
             double timeout_s = 10.0);
  ~ArLiveView();
  ArLiveView(const ArLiveView&) = delete;
  ArLiveView& operator=(const ArLiveView&) = delete;

  // The next frame's composite; nullopt when the camera's stream ended. A camera that delivers
  // nothing within the timeout is an InputError naming it.
  std::optional<ar::LiveCompositeFrame> step();
  const CameraModel& camera() const;

 private:
  Installation& installation_;
  int index_;
  double timeout_s_;
  std::unique_ptr<ar::LiveComposite> composite_;
};

}  // namespace holo::pipeline
