#include "holo/pipeline/installation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "holo/calib/calibration_io.hpp"
#include "holo/capture/capture_config.hpp"
#include "holo/capture/simulated_source.hpp"
#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/core/log.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/relics.hpp"

namespace holo::pipeline {
namespace {

namespace fs = std::filesystem;

Model loadRelic(const ConfigNode& exhibit) {
  const ConfigNode field = exhibit["relic"];
  const std::string value = field.as<std::string>();
  const auto builtin = sim::builtinRelicNames();
  if (std::find(builtin.begin(), builtin.end(), value) != builtin.end()) {
    Model relic = sim::makeRelic(value, exhibit.file());
    sim::fitOnPedestal(relic);
    return relic;
  }
  const fs::path path = exhibit.pathBesideFile(value);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    field.fail("a glTF file (.gltf/.glb, relative to the configuration) or a built-in relic (" +
                   sim::relicNameList() + ")",
               "'" + value + "' (no such file: " + path.string() + ")");
  Model relic = loadGltf(path);
  if (relic.meshes.empty()) field.fail("a glTF file with at least one triangle mesh", path.string());
  if (exhibit.get<bool>("fit_relic", false)) sim::fitOnPedestal(relic);
  return relic;
}

cv::Mat loadPanorama(const ConfigNode& exhibit) {
  const ConfigNode field = exhibit["panorama"];
  const fs::path path = exhibit.pathBesideFile(field.as<std::string>());
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

// The model of configured camera `entry`: its calibration file when there is one, else the
// source's own (recordings and the simulation know theirs).
CameraModel cameraModelOf(const capture::CaptureConfig& config, const capture::CameraEntry& entry,
                          const capture::CameraSource& source) {
  const std::string serial = source.serial();
  std::error_code ec;
  if (!serial.empty()) {
    const fs::path file = calib::cameraCalibrationPath(config.calibration_dir, serial);
    if (fs::is_regular_file(file, ec)) {
      const calib::CameraCalibration calibration = calib::loadCameraCalibration(file);
      HOLO_LOG_INFO("camera {} (face {}): calibration {}", source.name(), entry.face, file.string());
      return calib::toCameraModel(calibration, file.string());
    }
  }
  if (const std::optional<CameraModel> model = source.cameraModel()) {
    HOLO_LOG_INFO("camera {} (face {}): no calibration file in {}, the source's own model", source.name(),
                  entry.face, config.calibration_dir.string());
    return *model;
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

Installation simulatedInstallation(const std::string& scene, bool paced, int panorama_width,
                                   const std::string& relic) {
  sim::SceneDescription description = sim::loadScene(scene);
  if (!relic.empty()) description.relic = relic;
  auto museum = std::make_shared<const sim::Museum>(std::move(description));
  Installation installation;
  installation.name = "scene " + museum->description().name;
  const int n = museum->cameraCount();
  installation.background.resize(static_cast<std::size_t>(n));
  tbb::parallel_for(0, n, [&](int i) {
    installation.background[static_cast<std::size_t>(i)] = museum->backgroundFrame(i);
  });
  for (int i = 0; i < n; ++i) {
    installation.sources.push_back(
        std::make_unique<capture::SimulatedSource>(museum, i, capture::SimulationOptions{.paced = paced}));
    installation.cameras.push_back(museum->camera(i));
    capture::CaptureOptions options;
    options.camera_id = i;
    installation.capture_options.push_back(options);
  }
  installation.simulated_cameras = true;
  installation.camera_exposure = museum->description().camera.exposure;
  installation.fps = museum->description().camera.fps;
  installation.relic = museum->relic();
  const int pw = std::max(64, panorama_width);
  installation.panorama = museum->renderPanorama(pw, pw / 2);
  return installation;
}

Installation loadInstallation(const ConfigNode& root) {
  const capture::CaptureConfig capture = capture::parseCaptureConfig(root["capture"]);
  if (capture.cameras.empty()) root["capture"].fail("at least one camera in capture.cameras");
  const ConfigNode exhibit = root["exhibit"];
  exhibit.rejectUnknownKeys(
      {"relic", "fit_relic", "panorama", "camera_exposure", "background_frames", "fps"});

  Installation installation;
  installation.name = root.file();
  installation.relic = loadRelic(exhibit);
  installation.panorama = loadPanorama(exhibit);
  installation.camera_exposure = exhibit.get<float>("camera_exposure", 1.0f);
  if (!(installation.camera_exposure > 0.0f) || !std::isfinite(installation.camera_exposure))
    exhibit["camera_exposure"].fail("a positive number");
  installation.background_frames = exhibit.get<int>("background_frames", 30);
  if (installation.background_frames < 0 || installation.background_frames > 10000)
    exhibit["background_frames"].fail("a number of frames in 0..10000");
  installation.fps = exhibit.get<double>("fps", 30.0);
  if (!(installation.fps > 0.0 && installation.fps <= 1000.0))
    exhibit["fps"].fail("a frame rate in Hz in (0, 1000]");

  // The pyramid file: where the panorama's directions point in the world.
  const fs::path pyramid = calib::pyramidCalibrationPath(capture.calibration_dir);
  std::error_code ec;
  if (fs::is_regular_file(pyramid, ec)) {
    installation.panorama_yaw_rad = calib::loadPyramidCalibration(pyramid).panorama_yaw_rad;
    HOLO_LOG_INFO("panorama yaw {:.2f} degrees from {}", installation.panorama_yaw_rad * 180.0f / kPi,
                  pyramid.string());
  } else {
    HOLO_LOG_WARN("{}: no pyramid calibration, the panorama is used unrotated (yaw 0)", pyramid.string());
  }

  installation.sources = capture::makeSources(capture);
  for (std::size_t i = 0; i < capture.cameras.size(); ++i) {
    installation.cameras.push_back(cameraModelOf(capture, capture.cameras[i], *installation.sources[i]));
    capture::CaptureOptions options = capture::makeCaptureOptions(capture, capture.cameras[i]);
    options.camera_id = static_cast<int>(i);  // the loop's camera index, not the face
    installation.capture_options.push_back(options);
  }
  installation.simulated_cameras =
      std::all_of(installation.sources.begin(), installation.sources.end(), [](const auto& source) {
        return dynamic_cast<const capture::SimulatedSource*>(source.get()) != nullptr;
      });
  return installation;
}

}  // namespace holo::pipeline
