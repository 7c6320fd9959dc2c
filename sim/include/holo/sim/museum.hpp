// The simulated museum: a hall, a virtual relic on the pyramid, visitors walking around it,
// four depth cameras on the sides of the base and a panorama of the hall. Used by the default
// demo, the simulated camera source and every regression test.
//
// Light model (why the numbers agree across renderers): everything real (hall, furniture,
// visitors and what they carry) is a diffuse emitter whose radiance is its Material::emission
// (lighting baked in), so a camera, the panorama and the path tracer all see the same radiance
// for the same surface; only the relic (virtual, seen by no camera) has a BRDF. A camera pixel is
// linearToSrgb8(exposure * radiance). Units: metres, seconds, linear radiance.
//
// Frames: world = pyramid frame (docs/architecture.md). The base top is y = 0, the floor y = -kBaseHeight.
// Face f in 0..3 is the side facing +Z, +X, -Z, -X (azimuth f * 90 degrees); camera f sits on
// that side of the base and looks outward. Time t = frame / fps. Everything is seeded:
// the same SceneDescription gives bit-identical output.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/core/mesh.hpp"
#include "holo/core/plinth.hpp"
#include "holo/core/rgbd_frame.hpp"
#include "holo/sim/halls.hpp"
#include "holo/sim/sensor_noise.hpp"
#include "holo/sim/visitors.hpp"

namespace holo::sim {

struct SceneDescription {
  std::string name;              // built-in name or file stem
  std::string source;            // file it came from, or "built-in"
  std::string hall = "gallery";  // room | gallery | atrium | window
  std::string relic = "vase";    // vase | kettle | tripod | sphere, or a glTF path
  bool fit_relic = true;         // scale and centre the relic on the pedestal
  // Overrides of the relic's material; negative means "keep the model's".
  float relic_roughness = -1.0f;
  float relic_metallic = -1.0f;
  int visitors = 3;
  // How the visitors (walking and close) look and move (visitors.hpp); scene key visitor_model.
  VisitorModel visitor_model = VisitorModel::bodies;
  // Visitors standing close to the pyramid, looking at it and reaching out to it (visitors.hpp's
  // planCloseVisitors), after the walking ones; 0..4. None in the built-in scenes, so their
  // walkers stay as they are; the reflection evaluation (eval tracer) adds one.
  int close_visitors = 0;
  std::uint64_t seed = 1;
  CameraSettings camera;
  SensorNoise noise = sensorProfile(SensorProfile::structured_light);
  vec3 panorama_position{0.0f, 0.35f, 0.0f};
  // A virtual plinth under the relic (core/plinth.hpp), for the renderers only: the simulated
  // hall and cameras do not see it. Scene key plinth; absent: none.
  std::optional<PlinthSettings> plinth;
};

// A built-in name ("museum", "room", "gallery", "atrium", "window", "empty", ...) or a YAML file. Throws
// InputError naming the file and field for a bad file or an unknown name (listing the names).
SceneDescription loadScene(const std::string& name_or_file);
std::vector<std::string> builtinSceneNames();
std::vector<std::string> builtinRelicNames();
// One line about a built-in scene (hall, relic, visitors); empty for an unknown name.
std::string describeBuiltinScene(const std::string& name);

// One simulated camera frame and what a perfect sensor would have given.
struct SimulatedFrame {
  RgbdFrame frame;     // noisy, as the sensor delivers it
  cv::Mat true_depth;  // CV_32FC1, metres, 0 where nothing is within range
  cv::Mat foreground;  // CV_8UC1, 255 where the pixel sees a visitor or what they carry
};

class Museum {
 public:
  explicit Museum(SceneDescription description);
  ~Museum();
  Museum(Museum&&) noexcept;
  Museum& operator=(Museum&&) noexcept;

  const SceneDescription& description() const;
  // The rig's cameras, 0..kFaceCount-1.
  int cameraCount() const { return kFaceCount; }
  // The check camera (index kCheckCamera): a camera of the rig's intrinsics on a tripod in the
  // hall, behind face 0 and to its right, looking down at the relic (eye kCheckCameraEye, looking
  // at kCheckCameraTarget): what a technician sets up to see the AR check view, since the rig's
  // cameras look outward and never see the relic. No part of the rig: the frame loop ignores it.
  static constexpr int kCheckCamera = kFaceCount;
  static constexpr vec3 kCheckCameraEye{0.25f, 0.4f, 0.6f};
  static constexpr vec3 kCheckCameraTarget{0.0f, 0.08f, 0.0f};
  // A rig camera (0..cameraCount()-1) or the check camera.
  const CameraModel& camera(int index) const;
  float frameTime(int frame) const;

  // The relic in the world frame (standing on the base top, centred on the Y axis).
  const Model& relic() const;
  // The static hall: walls, floor, furniture, the pyramid base (emissive materials).
  const Model& hall() const;
  // Visitors and what they carry, posed at this frame (emissive materials).
  Model visitors(int frame) const;
  // Head centre of every visitor at this frame (world, metres), in visitor order.
  std::vector<vec3> visitorHeads(int frame) const;

  // Renders camera `index` (a rig camera or the check camera) at `frame` with Embree. `with_visitors = false`
  // gives the empty hall. `time_offset_s` poses the visitors that much after the frame's time (a depth device
  // whose frames lag the colour device's); the sensor noise stays the frame's.
  SimulatedFrame renderCamera(int index, int frame, bool with_visitors = true,
                              double time_offset_s = 0.0) const;
  // The background frame gamma_s of a camera: the empty hall, with sensor noise.
  RgbdFrame backgroundFrame(int index) const;
  // Equirectangular linear HDR (CV_32FC3 BGR) of the empty hall seen from panorama_position;
  // the pixel/direction mapping is the one in holo/core/equirect.hpp.
  cv::Mat renderPanorama(int width, int height) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace holo::sim
