#include "holo/pipeline/installation.hpp"

#include <fmt/format.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <utility>

#include "holo/calib/calibration_io.hpp"
#include "holo/capture/capture_config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/core/log.hpp"
#include "holo/depthfilter/depth_filter_config.hpp"
#include "holo/pipeline/exhibit_config.hpp"
#include "holo/relics/relics.hpp"

namespace holo::pipeline {
namespace {

namespace fs = std::filesystem;

// The files the parsed section names, loaded now; a missing or unreadable one fails naming its
// field (`node`: the section or the playlist entry).
Model loadRelic(const ConfigNode& node, const std::string& builtin_relic, const fs::path& relic_file,
                bool fit_relic) {
  if (!builtin_relic.empty()) {
    Model relic = relics::makeRelic(builtin_relic, node.file());
    relics::fitOnPedestal(relic);
    return relic;
  }
  const ConfigNode field = node["relic"];
  std::error_code ec;
  if (!fs::is_regular_file(relic_file, ec))
    field.fail("a glTF file (.gltf/.glb, relative to the configuration) or a built-in relic (" +
                   relics::relicNameList() + ")",
               "'" + field.as<std::string>() + "' (no such file: " + relic_file.string() + ")");
  Model relic;
  try {
    relic = loadGltf(relic_file);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    field.fail("a readable glTF 2.0 file", relic_file.string() + ": " + e.what());
  }
  if (relic.meshes.empty()) field.fail("a glTF file with at least one triangle mesh", relic_file.string());
  if (fit_relic) relics::fitOnPedestal(relic);
  return relic;
}

cv::Mat loadPanorama(const ConfigNode& node, const fs::path& path) {
  const ConfigNode field = node["panorama"];
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    field.fail("an equirectangular HDR panorama (.hdr or .exr, relative to the configuration)",
               "'" + field.as<std::string>() + "' (no such file: " + path.string() + ")");
  HdrImage hdr = loadHdr(path);
  if (hdr.pixels.cols != 2 * hdr.pixels.rows)
    field.fail(
        "an equirectangular panorama (width = 2 x height)",
        std::to_string(hdr.pixels.cols) + "x" + std::to_string(hdr.pixels.rows) + " (" + path.string() + ")");
  return hdr.pixels;
}

// The pyramid (the world origin) and its base must stand inside the hall the panorama is
// projected onto.
void checkHallRadius(const ConfigNode& node, const reflect::PanoramaProxy& proxy) {
  const float base_reach = std::sqrt(2.0f) * proxy.base_half_width;  // to a corner
  if (!proxy.infinite() && proxy.radius <= glm::length(proxy.centre) + base_reach + 0.5f)
    node[node.has("hall_radius") ? "hall_radius" : "relic"].fail(
        "a radius at least 0.5 m beyond the pyramid and its base (the panorama was captured " +
        fmt::format("{:.2f}", glm::length(proxy.centre)) +
        " m from it, pyramid.yml's panorama_position; the base's corners reach " +
        fmt::format("{:.2f}", base_reach) + " m, exhibit.base_half_width)");
}

struct CalibratedCamera {
  CameraModel model;
  vec3 colour_gains{1.0f};
  float depth_correction = 1.0f;
  std::optional<capture::DepthToColour> depth_to_colour;
};

// The model of configured camera `entry`: its calibration file when there is one, else the
// source's own (recordings and the simulation know theirs).
CalibratedCamera calibratedCameraOf(const capture::CaptureConfig& config, const capture::CameraEntry& entry,
                                    const capture::CameraSource& source) {
  const std::string serial = source.serial();
  std::error_code ec;
  if (!serial.empty()) {
    const fs::path file = calib::cameraCalibrationPath(config.calibration_dir, serial);
    if (fs::is_regular_file(file, ec)) {
      const calib::CameraCalibration calibration = calib::loadCameraCalibration(file);
      HOLO_LOG_INFO("camera {} (face {}): calibration {}", source.name(), entry.face, file.string());
      float depth_correction = 1.0f;
      if (calibration.depth_scale_fitted) {
        depth_correction = static_cast<float>(calibration.depth_scale / source.metresPerDepthUnit());
        HOLO_LOG_INFO("camera {}: fitted depth scale {:.6g} m per unit against the nominal {:.6g} (x{:.4f})",
                      source.name(), calibration.depth_scale, source.metresPerDepthUnit(), depth_correction);
        // A fitted scale more than 20% off its nominal one is a wrong unit, not a calibration.
        if (!(depth_correction > 0.8f && depth_correction < 1.25f))
          throw InputError(file.string(), "depth_scale",
                           "a fitted scale within 20% of the source's nominal " +
                               fmt::format("{:g}", source.metresPerDepthUnit()) +
                               " metres per raw unit (capture.cameras[].depth.depth_scale)",
                           fmt::format("{:g}", calibration.depth_scale));
      }
      std::optional<capture::DepthToColour> depth_to_colour;
      if (calibration.depth_intrinsics) {
        depth_to_colour.emplace(*calibration.depth_intrinsics, calibration.intrinsics,
                                calibration.T_colour_depth);
        HOLO_LOG_INFO("camera {}: depth from a second device ({}x{}), reprojected into the colour image",
                      source.name(), calibration.depth_intrinsics->width,
                      calibration.depth_intrinsics->height);
      }
      return {calib::toCameraModel(calibration, file.string()), calibration.colour_gains, depth_correction,
              std::move(depth_to_colour)};
    }
  }
  if (const std::optional<CameraModel> model = source.cameraModel()) {
    HOLO_LOG_INFO("camera {} (face {}): no calibration file in {}, the source's own model", source.name(),
                  entry.face, config.calibration_dir.string());
    return {*model, vec3(1.0f), 1.0f, std::nullopt};
  }
  const std::string expected_file =
      serial.empty() ? (config.calibration_dir / "camera_SERIAL.yml").string()
                     : calib::cameraCalibrationPath(config.calibration_dir, serial).string();
  throw InputError(expected_file, "capture.cameras (face " + std::to_string(entry.face) + ")",
                   "a calibration file for camera '" + source.name() +
                       "' (holopyramid calibrate writes it; capture.calibration_dir says where)",
                   "no such file, and the source does not know its model");
}

}  // namespace

bool describesCameras(const ConfigNode& root) {
  return root.isMap() && root.has("capture");
}

bool describesPlaylist(const ConfigNode& root) {
  return root.isMap() && root.has("exhibit") && root["exhibit"].isMap() && root["exhibit"].has("relics");
}

void loadPlaylist(const ConfigNode& exhibit, const ExhibitConfig& config, Installation& installation) {
  installation.playlist.clear();
  installation.exhibit_problems = config.relic_problems;
  std::map<fs::path, cv::Mat> panoramas;  // by file: entries naming one hall share its pixels
  const ConfigNode relics = exhibit["relics"];
  for (const RelicEntryConfig& entry : config.relics) {
    const ConfigNode node = relics[static_cast<std::size_t>(entry.index)];
    try {
      ExhibitRelic relic;
      relic.name = entry.name;
      relic.index = entry.index;
      relic.relic = loadRelic(node, entry.builtin_relic, entry.relic_file, entry.fit_relic);
      // Placement about the relic's foot: scale, then turn, then lift.
      relic.relic.transform(glm::translate(mat4(1.0f), vec3(0.0f, entry.height_m, 0.0f)) *
                            glm::rotate(mat4(1.0f), glm::radians(entry.yaw_deg), vec3(0.0f, 1.0f, 0.0f)) *
                            glm::scale(mat4(1.0f), vec3(entry.scale)));
      if (!entry.panorama_file.empty()) {
        auto [it, added] = panoramas.try_emplace(entry.panorama_file);
        if (added) it->second = loadPanorama(node, entry.panorama_file);
        relic.panorama = it->second;
      } else if (!config.panorama_file.empty() || !installation.panorama.empty()) {
        relic.panorama = installation.panorama;
      } else {
        node["relic"].fail("a panorama: exhibit.relics[" + std::to_string(entry.index) +
                               "].panorama or exhibit.panorama (the installation has no hall of its own)",
                           "none");
      }
      relic.panorama_yaw_rad = installation.panorama_yaw_rad;
      relic.panorama_proxy = installation.panorama_proxy;
      if (entry.hall_radius_m) relic.panorama_proxy.radius = *entry.hall_radius_m;
      if (entry.base_half_width_m) relic.panorama_proxy.base_half_width = *entry.base_half_width_m;
      checkHallRadius(node, relic.panorama_proxy);
      relic.duration_s = entry.duration_s;
      relic.turntable_deg_per_s = entry.turntable_deg_per_s;
      relic.crossfade_s = entry.crossfade_s;
      installation.playlist.push_back(std::move(relic));
    } catch (const std::exception& e) {  // InputError, or a decoder's own
      installation.exhibit_problems.push_back("entry " + std::to_string(entry.index) + " (" + entry.name +
                                              "): " + e.what());
    }
  }
  for (const std::string& problem : installation.exhibit_problems)
    HOLO_LOG_WARN("exhibit playlist: {} (left out)", problem);
  if (installation.playlist.empty()) {
    std::string why;
    for (const std::string& problem : installation.exhibit_problems)
      why += (why.empty() ? "" : "; ") + problem;
    relics.fail("at least one relic that loads", why);
  }
  const ExhibitRelic& first = installation.playlist.front();
  installation.relic = first.relic;
  installation.relic_name = first.name;
  installation.panorama = first.panorama;
  installation.panorama_yaw_rad = first.panorama_yaw_rad;
  installation.panorama_proxy = first.panorama_proxy;
  HOLO_LOG_INFO("exhibit playlist: {} relics, {} left out", installation.playlist.size(),
                installation.exhibit_problems.size());
}

std::optional<RgbdFrame> loadCalibratedBackground(const fs::path& dir, std::size_t index, cv::Size size) {
  const fs::path colour_file = dir / ("background_camera" + std::to_string(index) + ".png");
  const fs::path depth_file = dir / ("background_depth_camera" + std::to_string(index) + ".png");
  std::error_code ec;
  if (!fs::is_regular_file(colour_file, ec) || !fs::is_regular_file(depth_file, ec)) return std::nullopt;
  const auto check = [&](const fs::path& file, const cv::Mat& image, int type, const std::string& kind) {
    if (image.empty() || image.type() != type || image.size() != size)
      throw InputError(file.string(), "",
                       kind + " of " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                           " (the camera's calibrated size)",
                       image.empty() ? std::string("not a readable PNG")
                                     : std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                                           " of type " + std::to_string(image.type()));
  };
  RgbdFrame frame;
  frame.colour = cv::imread(colour_file.string(), cv::IMREAD_COLOR);
  check(colour_file, frame.colour, CV_8UC3, "an 8-bit colour PNG");
  const cv::Mat depth_mm = cv::imread(depth_file.string(), cv::IMREAD_ANYDEPTH);
  check(depth_file, depth_mm, CV_16UC1, "a 16-bit depth PNG in millimetres");
  depth_mm.convertTo(frame.depth, CV_32FC1, 0.001);
  return frame;
}

void readDepthFilterSection(const ConfigNode& root, Installation& installation) {
  const std::optional<ConfigNode> section = root.find("depthfilter");
  if (!section) return;
  installation.depth_filter = depthfilter::parseDepthFilterConfig(*section);
  installation.cross_camera_fill = depthfilter::parseCrossCameraFillConfig(*section);
  installation.foreground_mask = depthfilter::parseForegroundMaskConfig(*section);
  installation.foreground_scale = depthfilter::parseForegroundScale(*section);
  installation.foreground_full_size_outline =
      depthfilter::parseFullSizeOutline(*section, installation.foreground_scale);
}

Installation loadInstallation(const ConfigNode& root, const InstallationOptions& installation_options) {
  const capture::CaptureConfig capture = capture::parseCaptureConfig(root["capture"]);
  if (capture.cameras.empty()) root["capture"].fail("at least one camera in capture.cameras");
  const ConfigNode exhibit = root["exhibit"];
  const ExhibitConfig exhibit_config = parseExhibitConfig(exhibit);

  Installation installation;
  installation.name = root.file();
  if (!exhibit_config.playlist())
    installation.relic =
        loadRelic(exhibit, exhibit_config.builtin_relic, exhibit_config.relic_file, exhibit_config.fit_relic);
  if (!exhibit_config.panorama_file.empty())
    installation.panorama = loadPanorama(exhibit, exhibit_config.panorama_file);
  installation.camera_exposure = exhibit_config.camera_exposure;
  installation.background_frames = exhibit_config.background_frames;
  installation.fps = exhibit_config.fps;
  installation.plinth = exhibit_config.plinth;
  readDepthFilterSection(root, installation);

  // The pyramid file: where the panorama's directions point in the world.
  const fs::path pyramid = calib::pyramidCalibrationPath(capture.calibration_dir);
  std::error_code ec;
  if (exhibit_config.hall_radius_m) installation.panorama_proxy.radius = *exhibit_config.hall_radius_m;
  installation.panorama_proxy.base_half_width = exhibit_config.base_half_width_m;
  if (fs::is_regular_file(pyramid, ec)) {
    const calib::PyramidCalibration calibration = calib::loadPyramidCalibration(pyramid);
    installation.panorama_yaw_rad = calibration.panorama_yaw_rad;
    installation.panorama_proxy.centre = calibration.panorama_position;
    HOLO_LOG_INFO("panorama yaw {:.2f} degrees, captured at ({:.2f}, {:.2f}, {:.2f}) m from {}",
                  installation.panorama_yaw_rad * 180.0f / kPi, calibration.panorama_position.x,
                  calibration.panorama_position.y, calibration.panorama_position.z, pyramid.string());
  } else {
    HOLO_LOG_WARN("{}: no pyramid calibration, the panorama is used unrotated (yaw 0)", pyramid.string());
  }
  if (exhibit_config.playlist()) {
    loadPlaylist(exhibit, exhibit_config, installation);
  } else {
    checkHallRadius(exhibit, installation.panorama_proxy);
    installation.relic_name = exhibit["relic"].as<std::string>();
  }

  installation.sources = capture::makeSources(capture, installation_options.simulated_sources);
  for (std::size_t i = 0; i < capture.cameras.size(); ++i) {
    const CalibratedCamera camera = calibratedCameraOf(capture, capture.cameras[i], *installation.sources[i]);
    installation.cameras.push_back(camera.model);
    installation.colour_gains.push_back(camera.colour_gains);
    installation.depth_correction.push_back(camera.depth_correction);
    installation.depth_to_colour.push_back(camera.depth_to_colour);
    capture::CaptureOptions options = capture::makeCaptureOptions(capture, capture.cameras[i]);
    options.camera_id = static_cast<int>(i);  // the loop's camera index, not the face
    installation.capture_options.push_back(options);
  }
  // The background the calibration captured, unless asked to learn it again; only when every
  // camera has one (the loop's learning frames serve all cameras at once).
  if (!installation_options.relearn_background) {
    std::vector<RgbdFrame> background;
    for (std::size_t i = 0; i < installation.cameras.size(); ++i) {
      const CameraModel& camera = installation.cameras[i];
      std::optional<RgbdFrame> frame =
          loadCalibratedBackground(capture.calibration_dir, i, {camera.width(), camera.height()});
      if (!frame) {
        HOLO_LOG_INFO("camera {}: no captured background in {}, learning it from the first {} frames", i,
                      capture.calibration_dir.string(), installation.background_frames);
        background.clear();
        break;
      }
      background.push_back(std::move(*frame));
    }
    if (!background.empty()) {
      HOLO_LOG_INFO("background of {} cameras from {} (--relearn-background learns it again)",
                    background.size(), capture.calibration_dir.string());
      installation.background = std::move(background);
      installation.background_frames = 0;
    }
  }
  installation.simulated_cameras = std::all_of(
      capture.cameras.begin(), capture.cameras.end(),
      [](const capture::CameraEntry& entry) { return entry.backend == capture::Backend::Simulated; });
  return installation;
}

}  // namespace holo::pipeline
