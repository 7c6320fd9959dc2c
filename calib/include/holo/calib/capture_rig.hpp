// Calibration on the configured cameras: any capture::CameraSource (the `capture:` section's
// Aravis and V4L2 cameras, recordings, simulated scenes, or a folder of photos) as a
// CalibrationRig. Frames are pulled from each source as the steps ask for them: a live camera
// delivers whatever the technician is doing in front of it, a recording replays what was done.
//
// No camera films the monitors, so the display step keeps the layout it is given (the previous
// pyramid.yml, or the default) and reports its dots where that layout puts them.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <vector>

#include "holo/calib/calibration_io.hpp"
#include "holo/calib/calibration_rig.hpp"
#include "holo/capture/camera_source.hpp"
#include "holo/capture/capture_config.hpp"

namespace holo::calib {

// A folder of photos (a sorted glob) as a camera: one photo per grab(), then EndOfStream. Every
// photo must have the first one's size (InputError naming the file otherwise).
class PhotoSource : public capture::CameraSource {
 public:
  PhotoSource(std::string serial, std::vector<std::string> files);
  // The files matching `pattern` (glob), sorted; InputError when none matches.
  static std::vector<std::string> expand(const std::string& pattern);

  std::string name() const override { return "photos:" + serial_; }
  std::string serial() const override { return serial_; }
  void open() override {}
  void start() override { next_ = 0; }
  void stop() override {}
  capture::GrabResult grab(Nanoseconds timeout) override;
  const std::vector<std::string>& files() const { return files_; }

 private:
  std::string serial_;
  std::vector<std::string> files_;
  std::size_t next_ = 0;
  cv::Size size_;
};

class CaptureRig : public CalibrationRig {
 public:
  // Opens and starts every source and waits for its first frame (its image size): a camera that
  // cannot be opened or delivers nothing within `silence` is an InputError naming it, so a
  // calibration never starts with a camera missing. `panorama`: CV_32FC3 linear BGR (may be
  // empty: then the panorama step fails with its hint). `stills`: the sources deliver unrelated
  // photos, not a video.
  CaptureRig(std::vector<std::unique_ptr<capture::CameraSource>> sources, cv::Mat panorama,
             PyramidCalibration display_layout, std::string description, bool stills = false,
             std::chrono::milliseconds silence = std::chrono::milliseconds(5000));
  ~CaptureRig() override;

  int cameraCount() const override { return static_cast<int>(cameras_.size()); }
  std::string serial(int camera) const override;
  cv::Size imageSize(int camera) const override;
  std::string describe() const override { return description_; }
  std::optional<RgbdFrame> nextFrame(int camera) override;
  bool stills() const override { return stills_; }
  double metresPerDepthUnit(int camera) const override;
  cv::Mat panorama() const override { return panorama_; }
  std::vector<cv::Point2f> observedTestPattern(int face, cv::Size view) const override;
  // The model the source itself carries (a recording's intrinsics and pose), for checking.
  std::optional<CameraModel> sourceModel(int camera) const;

 private:
  struct Camera {
    std::unique_ptr<capture::CameraSource> source;
    std::optional<RgbdFrame> pending;  // the first frame, grabbed to learn the image size
    cv::Size size;
    bool ended = false;
  };
  std::optional<RgbdFrame> grab(Camera& camera);

  std::vector<Camera> cameras_;
  cv::Mat panorama_;
  PyramidCalibration display_layout_;
  std::string description_;
  bool stills_;
  std::chrono::milliseconds silence_;
};

// The rig of a configuration file: the cameras of its `capture:` section (capture_config.hpp), the
// panorama of its `exhibit: panorama:` when given (else none), and the display layout of the
// calibration folder's pyramid.yml when there is one (else the default). InputError naming the
// file and field for anything wrong, or naming the camera that is missing.
struct ConfiguredRig {
  std::unique_ptr<CaptureRig> rig;
  std::filesystem::path calibration_dir;  // capture.calibration_dir: where the calibration goes
};
// `simulated` builds the sources of its sim cameras (capture::makeSources).
ConfiguredRig loadConfiguredRig(const std::filesystem::path& config_file,
                                const capture::SourceFactory& simulated = {});

}  // namespace holo::calib
