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
#include <string>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/core/mesh.hpp"
#include "holo/core/rgbd_frame.hpp"
#include "holo/sim/visitors.hpp"

namespace holo::sim {

inline constexpr float kBaseHeight = 1.0f;  // floor to base top, metres
inline constexpr int kFaceCount = 4;

// Which kind of depth camera the sensor model imitates (docs/sim.md, "Sensor profiles").
//   uniform          : Gaussian noise, holes at grazing angles, on depth edges and scattered at
//                      random (salt-like).
//   structured-light : Kinect-like, fitted to real TUM RGB-D frames: the projector's shadow beside
//                      depth edges, holes in patches on dark, metal, glossy and glancing surfaces
//                      and towards the range limit, disparity quantisation, holes that flicker
//                      frame to frame. Every built-in scene's and scene file's default.
//   stereo           : ZED-like: holes in patches on low-texture surfaces, the second camera's
//                      occlusion beside depth edges, foreground fattened over the background.
enum class SensorProfile { uniform, structured_light, stereo };

struct SensorNoise {
  SensorProfile profile = SensorProfile::uniform;
  // Depth noise standard deviation sigma(z) = sigma_0 + k_z1 * z + k_z2 * z^2 (metres).
  float sigma_0 = 0.001f;
  float k_z1 = 0.0f;
  float k_z2 = 0.0025f;
  float grazing_dropout_deg = 78.0f;  // beyond this angle between ray and normal, no depth
  float edge_dropout = 0.5f;          // probability of dropping a pixel on a depth edge
  float flying_pixel = 0.3f;          // probability an edge pixel takes a mixed depth
  float random_dropout = 0.01f;       // probability any pixel has no depth
  float colour_sigma = 2.0f;          // colour noise, 8-bit steps
  bool enabled = true;

  // The structured-light and stereo profiles only (the uniform profile ignores these).
  // Projector-camera (or camera-camera) baseline along the image +x axis, metres: pixels the
  // projector (second camera) cannot see have no depth.
  float baseline = 0.075f;
  // Disparity is measured in steps of disparity_step_px at native_focal_px (the sensor's own
  // resolution, whatever the image's): depth comes in steps of z^2 * step / (focal * baseline).
  float native_focal_px = 580.0f;
  float disparity_step_px = 0.125f;
  float grazing_start_deg = 60.0f;  // hole probability ramps from 0 here to 1 at grazing_dropout_deg
  // Surfaces whose albedo luminance (without a material: the radiance's luminance) is below
  // dark_luminance lose up to dark_dropout of their pixels: all of it at albedo 0, none at the
  // threshold (the projector's infrared comes back too weak from dark clothes and hair).
  float dark_luminance = 0.0f;
  float dark_dropout = 0.0f;
  // Metal returns no diffuse pattern: a pixel on it is lost with probability metal_dropout x
  // metallic x (1 - roughness) (brushed metal scatters some of it back).
  float metal_dropout = 0.0f;
  // A smooth surface (roughness below 0.5) seen within highlight_deg of head-on mirrors the
  // projector into the camera and saturates it: up to highlight_dropout lost, all of it at
  // roughness 0 and head-on, fading to none at roughness 0.5 and at highlight_deg.
  float highlight_deg = 0.0f;
  float highlight_dropout = 0.0f;
  float range_fade_start = 20.0f;  // hole probability ramps from 0 here to 1 at range_fade_end
  float range_fade_end = 20.0f;
  float edge_band_px = 1.0f;          // edge_dropout applies within this many pixels of a depth edge
  float low_texture_contrast = 0.0f;  // stereo: 7x7 sRGB contrast (8-bit steps) below which ...
  float low_texture_dropout = 0.0f;   // ... pixels lose depth with this probability
  float edge_fattening_px = 0.0f;     // stereo: foreground depth spreads this far over the background
  float hole_patch_px = 8.0f;         // holes come in patches about this wide
  float hole_flicker = 0.3f;          // share of the patch pattern that changes every frame
};

// "uniform", "structured-light", "stereo"; sensorProfileFromName throws InputError(origin,
// field, ...) for another name.
const char* sensorProfileName(SensorProfile profile);
SensorProfile sensorProfileFromName(const std::string& name, const std::string& origin = "",
                                    const std::string& field = "sensor");
std::vector<std::string> sensorProfileNames();
// The profile's parameters (fitted ones for structured-light).
SensorNoise sensorProfile(SensorProfile profile);

struct CameraSettings {
  int width = 640;
  int height = 360;
  float hfov_deg = 110.0f;
  float vfov_deg = 70.0f;
  // Upwards tilt of the optical axis. 8 degrees sees the heads of visitors >= ~1 m away; a visitor
  // standing within ~0.6 m of the pyramid shows only from the waist to the chest: a rig for close
  // visitors needs more (eval tracer uses 20 degrees with vfov 90).
  float tilt_deg = 8.0f;
  float min_range = 0.2f;
  float max_range = 20.0f;
  float fps = 30.0f;
  float exposure = 1.0f;
};

struct SceneDescription {
  std::string name;              // built-in name or file stem
  std::string source;            // file it came from, or "built-in"
  std::string hall = "gallery";  // room | gallery | atrium
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
};

// A built-in name ("museum", "room", "gallery", "atrium", "empty", ...) or a YAML file. Throws
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
  int cameraCount() const { return kFaceCount; }
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

  // Renders camera `index` at `frame` with Embree. `with_visitors = false` gives the empty hall.
  // `time_offset_s` poses the visitors that much after the frame's time (a depth device whose
  // frames lag the colour device's); the sensor noise stays the frame's.
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
