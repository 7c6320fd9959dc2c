// The AR check view of one of an installation's cameras (ar/ar_view.hpp): one frame grabbed
// from the camera (its depth corrected like the frame loop's: the fitted depth scale, the
// reprojection of a second device's depth into the colour image), the camera refused with an
// InputError naming it and what is needed (ar::requireArCamera), the relic of the installation
// composited over the frame with its shadow and light. Units: metres, world (pyramid) frame.
#pragma once

#include "holo/ar/ar_view.hpp"
#include "holo/pipeline/installation.hpp"

namespace holo::pipeline {

// Grabs one frame of camera `index` (waiting up to `timeout_s` seconds for it) and renders its
// composite. `settings.exposure` and `settings.panorama_yaw_rad` are the installation's.
ar::ArView arCheckView(Installation& installation, int index, ar::ArViewSettings settings,
                       double timeout_s = 10.0);

}  // namespace holo::pipeline
