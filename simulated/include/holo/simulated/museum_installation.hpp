// The simulated museum as an installation the frame loop runs on (pipeline/installation.hpp): its
// four simulated cameras with their true models, its check camera (sim::Museum::kCheckCamera, for
// the AR check view), its relic, its rendered hall panorama placed
// where the hall is, and its empty hall as the background. The default demo and kiosk content.
// Units: metres in the world (pyramid) frame.
#pragma once

#include <string>

#include "holo/pipeline/frame_loop.hpp"
#include "holo/pipeline/installation.hpp"
#include "holo/reflect/environment.hpp"

namespace holo::sim {
class Museum;
}

namespace holo::simulated {

// Where the simulated museum's panorama lies, for the live loop and the evaluations alike: the
// pyramid's base (sim::kBaseHalfWidth) and a sphere around the scene's panorama_position whose
// radius is the hall's mean distance from there (metres, over a Fibonacci sphere of directions,
// those the base hides left out). Infinite (the panorama at infinity, no base) for a hall with
// no geometry (hall: none).
reflect::PanoramaProxy museumPanoramaProxy(const sim::Museum& museum);

// The simulated museum's scene `scene` (built-in name or YAML file). `paced`: the cameras deliver
// frames at the scene's rate (live mode); else as fast as they are asked for (deterministic).
// `relic` (built-in name or glTF file) replaces the scene's relic; empty: the scene's. The
// panorama lies where the hall is (museumPanoramaProxy).
pipeline::Installation museumInstallation(const std::string& scene, bool paced, int panorama_width,
                                          const std::string& relic = "");

// The installation `options` name: the configuration file options.config (its `capture:` cameras,
// sim ones included, and its `exhibit:`; InputError naming the file when it has no `capture:`
// section), else the simulated museum of options.scene with options.relic, paced when
// options.live, its panorama options.panorama_width wide.
pipeline::Installation installationFor(const pipeline::FrameLoopOptions& options);

}  // namespace holo::simulated
