// The scenes reflections are evaluated on (`holopyramid render`, `eval reflections`,
// `eval tracer`, `bench accuracy`): a relic, the real things around it that it reflects (the
// hall, the visitors), the hall's panorama beyond, the visitors as the depth cameras see them,
// and the view a face of the pyramid shows. Units: metres in the world (pyramid) frame, degrees
// where the name says so, linear HDR radiance in BGR images.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/core/mesh.hpp"
#include "holo/core/plinth.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"
#include "holo/reflect/environment.hpp"
#include "holo/reflect/frame_renderer.hpp"

namespace holo::eval {

struct SceneOptions {
  std::string scene = "empty";   // built-in scene name or YAML file; "empty" = relic alone
  std::string relic;             // built-in relic name or glTF file; empty = the scene's
  std::string hall;              // built-in hall name; empty = the scene's
  std::string panorama;          // HDR/EXR file; empty = the museum's rendered hall panorama
  bool fit = false;              // scale and centre a relic file on the pedestal
  int frame = 0;                 // museum frame (visitor poses)
  int close_visitors = -1;       // visitors standing close to the pyramid (sim); -1 = the scene's
  std::string visitor_model;     // "bodies" or "figures" (sim/visitors.hpp); empty = the scene's
  float camera_vfov_deg = 0.0f;  // the depth cameras' vertical field of view; 0 = the scene's
  float camera_tilt_deg = 0.0f;  // the depth cameras' upwards tilt; 0 = the scene's
  // The live renderers read the hall's panorama at infinity from its capture point instead of
  // through the hall's proxy (ReflectionScene::panorama_proxy): how the figures measured before
  // the proxy existed reproduce.
  bool panorama_at_infinity = false;
};

struct ViewOptions {
  int width = 256, height = 256;
  int face = 0;              // 0..3: +Z, +X, -Z, -X
  std::string eye, look_at;  // "X,Y,Z" (metres); empty = the face's default eye / relic centre
  float fov_deg = 0.0f;      // vertical; 0 = frame the relic
};

// The relic, the real things around it (emitters) and the environment beyond.
struct ReflectionScene {
  std::string scene_name, relic_name;
  Model relic;
  std::vector<Model> static_emitters;  // the hall
  Model visitors;                      // visitors and what they carry at the frame (may be empty)
  cv::Mat panorama;                    // linear HDR CV_32FC3 BGR, the static environment
  // Where the live renderers place the panorama's pixels (ours, SSRT and the static IBL read it
  // through this): with a hall, the pyramid's base and a sphere around the panorama's capture
  // point whose radius is the hall's mean distance from it over the directions the base leaves
  // (an installation's `exhibit.hall_radius`); without one (a panorama alone), at infinity. The
  // path-traced truth sees the hall's own geometry.
  reflect::PanoramaProxy panorama_proxy;
  depthfilter::ForegroundCloud foreground;  // the visitors as the depth cameras see them
  std::vector<reflect::ForegroundCameraImage> foreground_cameras;  // their colour and mask, per camera
  float floor_y = -1.0f;
  // A virtual plinth under the relic (the scene file's `plinth:`): the truth traces it as a
  // Lambert surface of the relic's (gt), ours draws it (TracerSettings::plinth); the other
  // methods leave it out.
  std::optional<PlinthSettings> plinth;
};

// Throws InputError naming the option ("--hall", a scene or relic file's field) for bad input.
ReflectionScene loadReflectionScene(const SceneOptions& options);

// The view where visitors matter most: among the frames of the first ten seconds (every third of
// a second) and the four faces, the one where the most relic pixels of a 48^2 face view see a
// visitor: by their mirror-reflected ray or, on glass, through the relic. Neutral to every method (true
// geometry, no renderer); "the face on the nearest visitor's side" left most views with no
// foreground reflection at all (docs/tracer/evaluation.md).
struct VisitorView {
  int frame = 0, face = 0;
  float reflected_fraction = 0.0f;  // of the relic's pixels whose mirror ray meets a visitor
  // Of the relic's pixels on a transmissive material whose view ray, continued straight through
  // the relic, meets a visitor (0 for an opaque relic): where visitors are seen through glass.
  float seen_through_fraction = 0.0f;
};
VisitorView visitorView(const SceneOptions& options);

// The scene of `eval tracer` and `bench accuracy`: a hall's built-in scene (its walkers) with
// `relic`, `close_visitors` standing close to the pyramid and the depth cameras tilted and opened
// as given, at the frame and face visitorView picks, seen by a size x size view of that face.
struct VisitorScene {
  ReflectionScene scene;
  CameraModel camera;
  VisitorView pick;
};
// visitor_model, panorama_at_infinity: as in SceneOptions.
VisitorScene visitorScene(const std::string& hall, const std::string& relic, int close_visitors,
                          float camera_tilt_deg, float camera_vfov_deg, int size,
                          const std::string& visitor_model = "", bool panorama_at_infinity = false);

// The camera of `view` on `scene`; throws InputError("command line", "--eye"/"--look-at", ...)
// for an unparsable point or an eye on the target.
CameraModel viewCamera(const ViewOptions& view, const ReflectionScene& scene);

}  // namespace holo::eval
