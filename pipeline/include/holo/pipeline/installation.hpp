// What the frame loop runs on: the cameras (their sources and calibrated models), the relic and
// the hall's panorama. Two origins:
//  * the simulated museum (`--scene`, the default): its four simulated cameras with their true
//    models, its relic and its rendered hall panorama, and its empty hall as the background;
//    holo::simulated assembles it (simulated/museum_installation.hpp), above this module;
//  * a configuration file (`--config FILE` with a `capture:` section, loadInstallation below):
//    the configured cameras (capture_config.hpp: Aravis, V4L2, recordings, and simulated scenes
//    through the caller's source factory), each camera's model from the calibration folder
//    (calibration_io.hpp: camera_SERIAL.yml, pyramid.yml for the panorama's yaw), and the
//    `exhibit:` section (exhibit_config.hpp: the relic, the panorama and their settings), and the
//    optional `depthfilter:` section (depth_filter_config.hpp).
//
// The background: when the calibration folder holds the background the calibration captured
// for every camera (background_cameraN.png, 8-bit BGR, and background_depth_cameraN.png, 16-bit
// millimetres as the camera measured them, 0 = invalid; N = the camera's index in capture.cameras;
// the loop corrects its depth like every frame's: fitted scale, reprojection), it is loaded and
// exhibit.background_frames is not spent relearning it; `relearn_background` (the commands'
// --relearn-background) ignores it and learns from the first frames as without one.
//
// Two-device cameras: a camera file with the depth device's intrinsics and T_colour_depth has its
// depth reprojected into the colour image before the foreground pipeline.
//
// The depth scale: a camera file whose depth_scale was fitted (depth_scale_fitted: 1) corrects
// the source's nominal scale (capture.cameras[i].depth.depth_scale, the recording's) by the ratio.
//
// A camera's model comes from DIR/camera_SERIAL.yml when the calibration folder has it, else
// from the source itself when it knows it (a recording, the simulation); a camera with neither
// is an error. Every error is a holo::InputError naming the file and the field.
// Units: metres in the world (pyramid) frame, radians for the yaw.
#pragma once

#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "holo/capture/camera_source.hpp"
#include "holo/capture/capture_config.hpp"
#include "holo/capture/capture_thread.hpp"
#include "holo/capture/depth_to_colour.hpp"
#include "holo/core/camera_model.hpp"
#include "holo/core/config.hpp"
#include "holo/core/mesh.hpp"
#include "holo/core/plinth.hpp"
#include "holo/core/rgbd_frame.hpp"
#include "holo/depthfilter/cross_camera_fill.hpp"
#include "holo/depthfilter/foreground_mask.hpp"
#include "holo/depthfilter/foreground_scale.hpp"
#include "holo/depthfilter/temporal_depth_filter.hpp"
#include "holo/reflect/environment.hpp"

namespace holo::pipeline {

struct ExhibitConfig;

// One relic of the exhibit's playlist, loaded and checked (exhibit.relics[i], exhibit_config.hpp):
// the relic placed (fitted, scaled, turned by its yaw, lifted), the hall it is shown in, and how
// long and how it is shown. Units: metres, radians, seconds, degrees per second.
struct ExhibitRelic {
  std::string name;  // the entry's `relic` value
  int index = 0;     // in exhibit.relics, from 0
  Model relic;       // world frame, standing on the base
  cv::Mat panorama;  // CV_32FC3 linear BGR; shared (not copied) between entries naming one file
  float panorama_yaw_rad = 0.0f;
  reflect::PanoramaProxy panorama_proxy;
  double duration_s = 60;
  double turntable_deg_per_s = 0;
  double crossfade_s = 1.5;
};

struct Installation {
  std::string name;  // for logs and reports: the scene's name or the configuration file
  // One entry per camera, in the same order: the source (not opened yet), its model in the world
  // frame, and its capture thread's settings (live mode).
  std::vector<std::unique_ptr<capture::CameraSource>> sources;
  std::vector<CameraModel> cameras;
  std::vector<capture::CaptureOptions> capture_options;
  // Check cameras: calibrated cameras that see the relic's place on the pyramid (a camera on a
  // tripod in the hall; the simulated museum's sim::Museum::kCheckCamera), for the AR check view
  // only (ar_check_view.hpp): the frame loop reads none of them. AR camera indices number the rig's
  // cameras first, then these (cameras.size() + k). Their frames are used as delivered (no depth
  // correction).
  std::vector<std::unique_ptr<capture::CameraSource>> check_sources;
  std::vector<CameraModel> check_cameras;
  // Every camera is simulated: rendering their frames is part of acquisition here, a cost no real
  // installation pays (the timing table shows it apart from the appliance's stages).
  bool simulated_cameras = false;
  // Background frames gamma_s given directly, one per camera (the simulated museum's empty hall);
  // may be empty. Then, or in addition, the first `background_frames` frames of every camera only
  // teach the foreground pipeline the background.
  std::vector<RgbdFrame> background;
  int background_frames = 0;
  float camera_exposure = 1.0f;  // radiance = srgbToLinear(colour) / camera_exposure
  // Per camera (same order), the calibration's colour gains: linear RGB multipliers matching its
  // colours to the other cameras' (calib/colour_gains.hpp); empty or 1 when not calibrated.
  std::vector<vec3> colour_gains;
  // Per camera (same order), the factor its depth is multiplied by: the calibration's fitted
  // metres per raw unit over the source's nominal one (1 when the scale was not fitted).
  std::vector<float> depth_correction;
  // Per camera (same order, may be shorter): for a camera whose depth comes from a second device,
  // the reprojection of its depth into the colour image (the calibration's T_colour_depth and
  // depth intrinsics); empty where colour and depth share one geometry.
  std::vector<std::optional<capture::DepthToColour>> depth_to_colour;
  double fps = 30.0;  // the cameras' frame rate
  // The temporal depth filter's settings: the configuration's `depthfilter:` section
  // (depth_filter_config.hpp), else the defaults.
  depthfilter::TemporalDepthFilterConfig depth_filter;
  // The cameras filling each other's holes: the cross_camera* fields of the same section.
  depthfilter::CrossCameraFillConfig cross_camera_fill;
  // The foreground's resolution divisor: the foreground_scale field of the same section.
  int foreground_scale = depthfilter::kDefaultForegroundScale;
  // A reduced foreground's outline redrawn at the camera's size: the full_size_outline field.
  bool foreground_full_size_outline = false;
  // The foreground mask's clean-up: the mask_* fields of the same section.
  depthfilter::ForegroundMaskConfig foreground_mask;
  Model relic;                           // world frame, standing on the base
  std::optional<PlinthSettings> plinth;  // exhibit.plinth: a virtual plinth drawn under the relic
  cv::Mat panorama;                      // CV_32FC3 linear BGR, equirectangular
  float panorama_yaw_rad = 0.0f;
  // Where the panorama's pixels are. Simulated: simulated::museumPanoramaProxy. Configured:
  // centre = its capture point (pyramid.yml's panorama_position), radius = exhibit.hall_radius,
  // base_half_width = exhibit.base_half_width; infinite (no parallax) without hall_radius.
  reflect::PanoramaProxy panorama_proxy;
  // The exhibit's playlist, the entries that load, in order (loadPlaylist); empty for a single
  // relic. With one, relic, panorama, panorama_yaw_rad and panorama_proxy above are its first
  // entry's (what the frame loop starts on).
  std::vector<ExhibitRelic> playlist;
  std::string relic_name;  // the relic shown first, for reports (the playlist's first entry's name)
  // The playlist's entries that were left out, each "entry N (NAME): why", N from 0.
  std::vector<std::string> exhibit_problems;
};

struct InstallationOptions {
  bool relearn_background = false;  // ignore the calibration's background (see above)
  // Builds the sources of the `capture:` section's sim cameras (simulated::configuredSources());
  // none: such a camera is an InputError (capture::makeSource).
  capture::SourceFactory simulated_sources = {};
};

// The installation a configuration document describes (`root` is the whole document; its
// `capture:` and `exhibit:` sections are read). Throws InputError naming the file and field.
Installation loadInstallation(const ConfigNode& root, const InstallationOptions& options = {});

// The background the calibration captured for camera `index` (see above), checked against the
// camera's image size; nullopt when either file is absent. InputError naming the file when it is
// not a picture of that size and kind.
std::optional<RgbdFrame> loadCalibratedBackground(const std::filesystem::path& calibration_dir,
                                                  std::size_t index, cv::Size size);

// The document's `depthfilter:` section, when it has one, into `installation`'s depth filter,
// cross-camera fill, mask and foreground resolution (every field optional; InputError naming the
// file and field). loadInstallation reads it; so does a run on the simulated museum.
void readDepthFilterSection(const ConfigNode& root, Installation& installation);

// True when the document has a `capture:` section (then it describes real cameras).
bool describesCameras(const ConfigNode& root);
// True when the document's `exhibit:` section has a playlist (`relics:`).
bool describesPlaylist(const ConfigNode& root);

// Loads the playlist of `config` (parsed from `exhibit`, the section's node) into `installation`:
// every entry's relic and panorama files are read and checked now (so every broken entry is known
// from the first frame); an entry naming no panorama is shown in the installation's own hall
// (installation.panorama, its yaw and proxy, with the entry's hall_radius and base_half_width
// when it sets them). An entry that fails is left out and reported in exhibit_problems with the
// parser's problems. Throws InputError naming exhibit.relics when no entry loads. Then relic,
// panorama, panorama_yaw_rad and panorama_proxy become the first entry's.
void loadPlaylist(const ConfigNode& exhibit, const ExhibitConfig& config, Installation& installation);

}  // namespace holo::pipeline
