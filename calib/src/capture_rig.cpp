#include "holo/calib/capture_rig.hpp"

#include <glob.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "holo/calib/display_alignment.hpp"
#include "holo/capture/capture_config.hpp"
#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/hdr_io.hpp"

namespace holo::calib {

PhotoSource::PhotoSource(std::string serial, std::vector<std::string> files)
    : serial_(std::move(serial)), files_(std::move(files)) {}

std::vector<std::string> PhotoSource::expand(const std::string& pattern) {
  glob_t found{};
  const int rc = ::glob(pattern.c_str(), 0, nullptr, &found);
  std::vector<std::string> files;
  if (rc == 0)
    for (std::size_t i = 0; i < found.gl_pathc; ++i) files.emplace_back(found.gl_pathv[i]);
  ::globfree(&found);
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError(pattern, "photos", "a pattern matching image files", "no match");
  return files;
}

capture::GrabResult PhotoSource::grab(Nanoseconds /*timeout*/) {
  capture::GrabResult result;
  if (next_ >= files_.size()) {
    result.status = capture::GrabStatus::EndOfStream;
    result.message = "no more photos";
    return result;
  }
  const std::string& file = files_[next_];
  result.frame.colour = cv::imread(file, cv::IMREAD_COLOR);
  if (result.frame.colour.empty()) throw InputError(file, "photo", "a readable image");
  if (size_.area() == 0) size_ = result.frame.colour.size();
  if (result.frame.colour.size() != size_)
    throw InputError(
        file, "image size",
        std::to_string(size_.width) + "x" + std::to_string(size_.height) + " like " + files_.front(),
        std::to_string(result.frame.colour.cols) + "x" + std::to_string(result.frame.colour.rows));
  result.frame.sequence = next_;
  result.frame.device_time = Nanoseconds(static_cast<std::int64_t>(next_) * 1'000'000'000);
  result.frame.host_time = Clock::now();
  result.status = capture::GrabStatus::Ok;
  ++next_;
  health().markFrame(result.frame.host_time);
  return result;
}

CaptureRig::CaptureRig(std::vector<std::unique_ptr<capture::CameraSource>> sources, cv::Mat panorama,
                       PyramidCalibration display_layout, std::string description, bool stills,
                       std::chrono::milliseconds silence)
    : panorama_(std::move(panorama)),
      display_layout_(display_layout),
      description_(std::move(description)),
      stills_(stills),
      silence_(silence) {
  if (sources.empty()) throw InputError(description_, "cameras", "at least one camera", "none");
  for (auto& source : sources) {
    Camera camera;
    camera.source = std::move(source);
    const std::string name = camera.source->name();
    try {
      camera.source->open();
      camera.source->start();
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      throw InputError(name, "camera",
                       "a camera that opens (connected, powered, not used by another program)", e.what());
    }
    cameras_.push_back(std::move(camera));
    Camera& added = cameras_.back();
    added.pending = grab(added);
    if (!added.pending)
      throw InputError(name, "frames", "at least one frame from every camera", "none: the camera is missing");
    added.size = added.pending->colour.size();
  }
}

CaptureRig::~CaptureRig() {
  for (Camera& camera : cameras_) camera.source->stop();
}

std::string CaptureRig::serial(int camera) const {
  const auto& source = *cameras_.at(static_cast<std::size_t>(camera)).source;
  std::string serial = source.serial().empty() ? source.name() : source.serial();
  // The serial names the camera's calibration file: keep it a file name.
  for (char& ch : serial)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_' && ch != '.') ch = '_';
  return serial;
}

cv::Size CaptureRig::imageSize(int camera) const {
  return cameras_.at(static_cast<std::size_t>(camera)).size;
}

std::optional<RgbdFrame> CaptureRig::grab(Camera& camera) {
  if (camera.ended) return std::nullopt;
  const auto give_up = Clock::now() + silence_;
  std::string last;
  while (Clock::now() < give_up) {
    capture::GrabResult result = camera.source->grab(std::chrono::milliseconds(200));
    switch (result.status) {
      case capture::GrabStatus::Ok:
        if (result.frame.colour.empty())
          throw InputError(camera.source->name(), "colour", "colour frames (the board is found in colour)",
                           "a frame without colour");
        return std::move(result.frame);
      case capture::GrabStatus::EndOfStream:
        camera.ended = true;
        return std::nullopt;
      case capture::GrabStatus::Disconnected:
        throw InputError(camera.source->name(), "camera", "connected", "disconnected: " + result.message);
      case capture::GrabStatus::Timeout:
      case capture::GrabStatus::Incomplete:
      case capture::GrabStatus::Failed:
        last = std::string(capture::toString(result.status)) + " " + result.message;
        break;
    }
  }
  throw InputError(camera.source->name(), "frames",
                   "a frame within " + std::to_string(silence_.count()) + " ms (check cable and power)",
                   "none (last: " + last + ")");
}

std::optional<RgbdFrame> CaptureRig::nextFrame(int camera) {
  Camera& cam = cameras_.at(static_cast<std::size_t>(camera));
  std::optional<RgbdFrame> frame;
  if (cam.pending) {
    frame = std::move(cam.pending);
    cam.pending.reset();
  } else {
    frame = grab(cam);
  }
  if (frame) frame->camera_id = camera;
  return frame;
}

double CaptureRig::metresPerDepthUnit(int camera) const {
  return cameras_.at(static_cast<std::size_t>(camera)).source->metresPerDepthUnit();
}

std::optional<CameraModel> CaptureRig::sourceModel(int camera) const {
  return cameras_.at(static_cast<std::size_t>(camera)).source->cameraModel();
}

std::vector<cv::Point2f> CaptureRig::observedTestPattern(int face, cv::Size view) const {
  const cv::Matx23d A = faceTransform(display_layout_.faces.at(static_cast<std::size_t>(face)), view);
  std::vector<cv::Point2f> placed;
  for (const auto& p : testPatternDots(view)) {
    const cv::Vec2d q = A * cv::Vec3d(p.x, p.y, 1.0);
    placed.emplace_back(static_cast<float>(q[0]), static_cast<float>(q[1]));
  }
  return placed;
}

ConfiguredRig loadConfiguredRig(const std::filesystem::path& config_file,
                                const capture::SourceFactory& simulated) {
  namespace fs = std::filesystem;
  const ConfigNode root = ConfigNode::loadFile(config_file);
  const capture::CaptureConfig config = capture::parseCaptureConfig(root["capture"]);
  cv::Mat panorama;
  if (const auto exhibit = root.find("exhibit"))
    if (const auto field = exhibit->find("panorama")) {
      const fs::path path = exhibit->pathBesideFile(field->as<std::string>());
      std::error_code ec;
      if (!fs::is_regular_file(path, ec))
        field->fail("an equirectangular HDR panorama (.hdr or .exr, relative to the configuration)",
                    "'" + field->as<std::string>() + "' (no such file: " + path.string() + ")");
      panorama = loadHdr(path).pixels;
    }
  PyramidCalibration layout;
  const fs::path pyramid_file = pyramidCalibrationPath(config.calibration_dir);
  std::error_code ec;
  if (fs::exists(pyramid_file, ec)) layout = loadPyramidCalibration(pyramid_file);
  ConfiguredRig out;
  out.calibration_dir = config.calibration_dir;
  out.rig = std::make_unique<CaptureRig>(capture::makeSources(config, simulated), panorama, layout,
                                         "the cameras of " + config_file.string());
  return out;
}

}  // namespace holo::calib
