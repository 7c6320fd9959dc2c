// `holopyramid simulate --scene NAME|FILE --frames N --out DIR`: records the simulated museum.
//
// DIR (a recording that `holopyramid info` and the recording source read):
//   recording.yaml, cam0..cam3/           the four cameras as the sensors deliver them (noisy):
//                                         rgb/*.png, depth/*.png (16-bit, millimetres), TUM index
//                                         files and associations.txt (capture/recording.hpp)
//   truth/cam<i>/depth/NNNNNN.png         noiseless depth, 16-bit millimetres, 0 = nothing in range
//   truth/cam<i>/foreground/NNNNNN.png    8-bit mask, 255 where the pixel sees a visitor
//   background/cam<i>/color.png, depth.png   the empty hall with sensor noise (gamma_s)
//   panorama.exr                          equirectangular linear HDR of the empty hall
//   contact_sheet.png                     frame 0 of every camera: colour, depth, truth, mask
//   scene.txt                             the scene's name, source and seed
// With --calibration, the recording starts with a calibration session (simulated::SimulatedRig: the
// intrinsics board held before every camera, the easel at each marked spot, the empty hall; its
// length is scene.txt's calibration_frames), the visitors' frames follow (truth/ names them by
// their recorded frame number), and installation.yaml describes the recording as an installation
// for `calibrate --auto --config` and `run --config`. The cameras then behave like a real
// installation's (sim/device_errors.hpp): colour and depth are two devices, the depth frames
// --depth-skew-ms later (depth.txt and associations.txt carry their own times; the visitors are
// posed at that time in the depth images), the depth --depth-scale-error off its nominal scale,
// each camera's colour with its own white balance; and the truth a calibration should find is
// written as a calibration folder:
//   truth/calibration/camera_SERIAL.yml   true intrinsics and pose, the true depth scale
//                                         (depth_scale_fitted: 1), the colour gains that match
//                                         the cameras (mean response / response per channel)
//   truth/calibration/pyramid.yml         panorama yaw 0 (panorama.exr is not turned), its
//                                         capture position, the default display layout
//
// The whole folder is written under DIR.partial-PID and renamed to DIR at the end, so DIR either
// does not exist or is complete. DIR must not exist yet.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "command.hpp"
#include "holo/capture/recorder.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/core/progress.hpp"
#include "holo/sim/device_errors.hpp"
#include "holo/sim/museum.hpp"
#include "holo/simulated/simulated_rig.hpp"

namespace holo::app {
namespace {

namespace fs = std::filesystem;

struct SimulateOptions {
  std::string scene;
  std::string sensor;         // empty: the scene's own
  std::string visitor_model;  // empty: the scene's own
  int frames = 30;
  std::string out;
  int panorama_width = 2048;
  bool calibration = false;
  int background_frames = 9;
  double depth_skew_ms = 15.0;
  double depth_scale_error = 0.02;
  bool quiet = false;
};

// The recording as an installation (`calibrate --auto --config`, `run --config`): every camera
// from the recording, the calibration written beside it, the scene's relic and the panorama.
std::string installationYaml(const sim::SceneDescription& scene, int cameras) {
  std::string yaml =
      "# Written by `holopyramid simulate --calibration`: the recording's cameras as an installation.\n"
      "#   holopyramid calibrate --auto --config installation.yaml   (writes calibration/)\n"
      "#   holopyramid run --config installation.yaml --headless\n"
      "capture:\n  calibration_dir: calibration\n  cameras:\n";
  for (int c = 0; c < cameras; ++c)
    yaml += "    - {face: " + std::to_string(c) +
            ", backend: recording, path: ., camera: " + std::to_string(c) + "}\n";
  yaml += "exhibit:\n  relic: " +
          (scene.relic.find('/') == std::string::npos ? scene.relic : std::string("vase")) +
          "\n  panorama: panorama.exr\n  fps: " + std::to_string(scene.camera.fps) + "\n";
  return yaml;
}

void writePng(const fs::path& path, const cv::Mat& image) {
  fs::create_directories(path.parent_path());
  writeAtomically(path, [&](const fs::path& tmp) {
    if (!cv::imwrite(tmp.string(), image)) throw Error("could not write " + path.string());
  });
}

std::string frameName(int frame) {
  char name[16];
  std::snprintf(name, sizeof name, "%06d.png", frame);
  return name;
}

// Depth as a picture: near = warm, far = cool, no measurement = black.
cv::Mat depthPicture(const cv::Mat& depth_m, float max_range) {
  cv::Mat scaled;
  depth_m.convertTo(scaled, CV_8U, -255.0 / max_range, 255.0);
  cv::Mat colour;
  cv::applyColorMap(scaled, colour, cv::COLORMAP_TURBO);
  colour.setTo(cv::Scalar::all(0), depth_m <= 0);
  return colour;
}

cv::Mat labelled(const cv::Mat& bgr, const std::string& label) {
  cv::Mat out = bgr.clone();
  cv::putText(out, label, {8, 24}, cv::FONT_HERSHEY_SIMPLEX, 0.7, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(out, label, {8, 24}, cv::FONT_HERSHEY_SIMPLEX, 0.7, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  return out;
}

// One column per camera; rows: colour, measured depth, true depth, foreground mask.
cv::Mat contactSheet(const std::vector<sim::SimulatedFrame>& first, float max_range) {
  std::vector<cv::Mat> columns;
  for (std::size_t i = 0; i < first.size(); ++i) {
    const auto& f = first[i];
    cv::Mat mask;
    cv::cvtColor(f.foreground, mask, cv::COLOR_GRAY2BGR);
    const std::string cam = "cam" + std::to_string(i);
    std::vector<cv::Mat> rows{labelled(f.frame.colour, cam + " colour"),
                              labelled(depthPicture(f.frame.depth, max_range), cam + " depth"),
                              labelled(depthPicture(f.true_depth, max_range), cam + " true depth"),
                              labelled(mask, cam + " foreground")};
    cv::Mat column;
    cv::vconcat(rows, column);
    columns.push_back(column);
  }
  cv::Mat sheet;
  cv::hconcat(columns, sheet);
  return sheet;
}

int simulate(const SimulateOptions& o) {
  if (o.frames < 1 || o.frames > 100000)
    throw InputError("", "--frames", "1 to 100000", std::to_string(o.frames));
  if (o.panorama_width < 16 || o.panorama_width % 2 != 0)
    throw InputError("", "--panorama-width", "an even width of at least 16 pixels",
                     std::to_string(o.panorama_width));
  const fs::path out = fs::absolute(o.out).lexically_normal();
  std::error_code ec;
  if (fs::exists(out, ec))
    throw InputError(out.string(), "--out", "a folder that does not exist yet", "it exists");

  sim::SceneDescription scene = sim::loadScene(o.scene);
  if (!o.sensor.empty())
    scene.noise = sim::sensorProfile(sim::sensorProfileFromName(o.sensor, "", "--sensor"));
  if (!o.visitor_model.empty())
    scene.visitor_model = sim::visitorModelFromName(o.visitor_model, "", "--visitor-model");
  const sim::Museum museum(scene);
  const int cameras = museum.cameraCount();
  std::optional<simulated::SimulatedRig> rig;
  int calibration_frames = 0;  // recorded before the visitors' frames
  if (!(o.depth_skew_ms >= 0.0 && o.depth_skew_ms < 1000.0 / scene.camera.fps))
    throw InputError("", "--depth-skew-ms", "0 up to a frame period", std::to_string(o.depth_skew_ms));
  if (!(o.depth_scale_error > -0.2 && o.depth_scale_error < 0.2))
    throw InputError("", "--depth-scale-error", "a share within (-0.2, 0.2)",
                     std::to_string(o.depth_scale_error));
  sim::DeviceErrors errors;
  errors.depth_skew_s = o.depth_skew_ms / 1000.0;
  errors.depth_scale_error = o.depth_scale_error;
  errors.seed = scene.seed;
  if (o.calibration) {
    calib::AutoCalibrationConfig config;
    config.intrinsics_board = calib::BoardSpec::parse(calib::kDefaultIntrinsicsBoard);
    config.placement_board = calib::BoardSpec::parse(calib::kDefaultPlacementBoard);
    config.placements = calib::defaultBoardPlacements(config.placement_board, cameras);
    if (o.background_frames < 1)
      throw InputError("", "--background-frames", "at least 1", std::to_string(o.background_frames));
    config.background_frames = o.background_frames;
    rig.emplace(scene, config);
    rig->setDepthDelay(errors.depth_skew_s);
    for (const auto activity : {calib::RigActivity::HandHeldBoard, calib::RigActivity::PlacementBoard,
                                calib::RigActivity::EmptyHall, calib::RigActivity::VerificationJig})
      calibration_frames += rig->frameCount(activity);
  }

  const fs::path tmp =
      out.parent_path() / (out.filename().string() + ".partial-" + std::to_string(::getpid()));
  fs::remove_all(tmp, ec);
  fs::create_directories(tmp);

  ProgressReporter progress(static_cast<std::int64_t>(o.frames + calibration_frames) * cameras + cameras + 1,
                            "simulate " + scene.name, o.quiet);
  std::vector<capture::RecorderCamera> recorder_cameras;
  for (int c = 0; c < cameras; ++c)
    recorder_cameras.push_back(
        {"cam" + std::to_string(c), "SIM-" + scene.name + "-" + std::to_string(c), museum.camera(c)});
  std::int64_t clipped = 0;
  {
    capture::Recorder recorder(tmp, recorder_cameras, capture::kDefaultDepthScale);
    std::vector<sim::SimulatedFrame> first;
    const auto stamp = [&](RgbdFrame& frame, int c, int recorded) {
      frame.camera_id = c;
      frame.sequence = static_cast<std::uint64_t>(recorded);
      frame.device_time = Nanoseconds(std::llround(recorded * 1e9 / static_cast<double>(scene.camera.fps)));
    };
    // With --calibration the depth is a second device: its own time, its scale error.
    const auto record = [&](RgbdFrame& frame, int c) {
      if (!rig) return recorder.write(frame);
      sim::applyDeviceErrors(errors, c, frame);
      recorder.write(frame, frame.device_time + Nanoseconds(std::llround(errors.depth_skew_s * 1e9)));
    };
    // The calibration session first, as the simulated technician acts it out for the wizard.
    if (rig) {
      int recorded = 0;
      for (const auto activity : {calib::RigActivity::HandHeldBoard, calib::RigActivity::PlacementBoard,
                                  calib::RigActivity::EmptyHall, calib::RigActivity::VerificationJig})
        for (int i = 0; i < rig->frameCount(activity); ++i, ++recorded)
          for (int c = 0; c < cameras; ++c) {
            RgbdFrame frame = rig->frame(activity, c, i);
            stamp(frame, c, recorded);
            record(frame, c);
            progress.update();
          }
    }
    for (int frame = 0; frame < o.frames; ++frame) {
      const int recorded = calibration_frames + frame;
      for (int c = 0; c < cameras; ++c) {
        sim::SimulatedFrame f = museum.renderCamera(c, frame);
        if (rig && errors.depth_skew_s > 0)
          f.frame.depth = museum.renderCamera(c, frame, true, errors.depth_skew_s).frame.depth;
        stamp(f.frame, c, recorded);
        record(f.frame, c);
        const fs::path truth = tmp / "truth" / ("cam" + std::to_string(c));
        writePng(truth / "depth" / frameName(recorded),
                 capture::depthToU16(f.true_depth, capture::kDefaultDepthScale, &clipped));
        writePng(truth / "foreground" / frameName(recorded), f.foreground);
        if (frame == 0) first.push_back(std::move(f));
        progress.update();
      }
    }
    recorder.finish();
    // Colour the depth over the range the scene actually spans, not the sensor's 20 m.
    double far = 0.5;
    for (const auto& f : first) {
      double hi = 0;
      cv::minMaxLoc(f.true_depth, nullptr, &hi);
      far = std::max(far, hi);
    }
    writePng(tmp / "contact_sheet.png",
             contactSheet(first, static_cast<float>(std::min<double>(far, scene.camera.max_range))));
  }
  for (int c = 0; c < cameras; ++c) {
    const RgbdFrame background = museum.backgroundFrame(c);
    const fs::path dir = tmp / "background" / ("cam" + std::to_string(c));
    writePng(dir / "color.png", background.colour);
    writePng(dir / "depth.png", capture::depthToU16(background.depth, capture::kDefaultDepthScale, &clipped));
    progress.update();
  }
  saveHdr(tmp / "panorama.exr", museum.renderPanorama(o.panorama_width, o.panorama_width / 2));
  progress.update();
  writeFileAtomically(
      tmp / "scene.txt",
      "scene: " + scene.name + "\nsource: " + scene.source + "\nseed: " + std::to_string(scene.seed) +
          "\nsensor: " + sim::sensorProfileName(scene.noise.profile) + "\nframes: " +
          std::to_string(o.frames) + "\ncalibration_frames: " + std::to_string(calibration_frames) + "\n" +
          (rig ? "depth_skew_ms: " + std::to_string(o.depth_skew_ms) +
                     "\ndepth_scale_error: " + std::to_string(o.depth_scale_error) + "\n"
               : std::string()));
  if (rig) {
    writeFileAtomically(tmp / "installation.yaml", installationYaml(scene, cameras));
    const fs::path truth = tmp / "truth" / "calibration";
    fs::create_directories(truth);
    const std::vector<vec3> gains = sim::matchingGains(errors, cameras);
    for (int c = 0; c < cameras; ++c) {
      calib::CameraCalibration camera =
          calib::fromCameraModel(museum.camera(c), recorder_cameras[static_cast<std::size_t>(c)].serial, 0.0,
                                 sim::trueMetresPerUnit(errors, 1.0 / capture::kDefaultDepthScale));
      camera.depth_scale_fitted = true;
      camera.colour_gains = gains[static_cast<std::size_t>(c)];
      calib::saveCameraCalibration(calib::cameraCalibrationPath(truth, camera.serial), camera);
    }
    calib::PyramidCalibration pyramid;
    pyramid.panorama_position = scene.panorama_position;
    calib::savePyramidCalibration(calib::pyramidCalibrationPath(truth), pyramid);
  }
  progress.done();
  fs::rename(tmp, out);
  std::cout << "wrote " << o.frames << " frames of " << cameras << " cameras of scene '" << scene.name
            << "' to " << out.string() << " (contact sheet: " << (out / "contact_sheet.png").string()
            << ")\n";
  if (clipped > 0) std::cout << "depth pixels beyond 65.5 m stored as 0: " << clipped << "\n";
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "simulate",
    [](CLI::App& sub) {
      auto o = std::make_shared<SimulateOptions>();
      sub.add_option("--scene", o->scene, "Built-in scene name or scene YAML file")->required();
      sub.add_option("--frames", o->frames, "Frames per camera")->capture_default_str();
      sub.add_option("--sensor", o->sensor,
                     "Depth-camera profile instead of the scene's: uniform, structured-light or stereo");
      sub.add_option("--visitor-model", o->visitor_model,
                     "Visitors instead of the scene's: bodies (the default) or figures");
      sub.add_option("--out", o->out, "Output folder (must not exist)")->required();
      sub.add_option("--panorama-width", o->panorama_width, "Panorama width in pixels")
          ->capture_default_str();
      sub.add_flag("--calibration", o->calibration,
                   "Record the calibration frames first (the hand-held board in front of each camera, the "
                   "easel at each marked spot, the empty hall) and write installation.yaml");
      sub.add_option("--background-frames", o->background_frames,
                     "With --calibration: frames of the empty hall")
          ->capture_default_str();
      sub.add_option("--depth-skew-ms", o->depth_skew_ms,
                     "With --calibration: how much later than colour each depth frame is taken")
          ->capture_default_str();
      sub.add_option("--depth-scale-error", o->depth_scale_error,
                     "With --calibration: true / nominal depth - 1 of every depth device")
          ->capture_default_str();
      sub.add_flag("-q,--quiet", o->quiet, "No progress output");
      return [o] { return simulate(*o); };
    },
    "Record the simulated museum: four RGB-D cameras, ground truth, backgrounds, panorama"});

}  // namespace holo::app
