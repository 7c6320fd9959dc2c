// Presenting the quad view: four face images in, the pyramid's display out.
//
// The frame loop renders one image per pyramid face (each from that face's eye position) and
// hands the four to present(). Two presenters share this interface:
//  * headless (EGL, Mesa surfaceless platform, an offscreen framebuffer): tests, CI, servers,
//    recording; readBack() returns the canvas (cross: the screen; monitors: a 2x2 sheet of the
//    four outputs, see canvasSize()).
//  * windows (GLFW): one fullscreen window per chosen monitor (monitors layout) or one window
//    (cross); with config.fullscreen = false, plain windows of config.output_size placed as the
//    2x2 sheet from the desktop's top-left corner.
// Both draw with the same shader and the same FacePlacement matrices (layout.hpp).
//
// Threads: a presenter is used from the thread that created it (GLFW requires the main thread).
// Faces: CV_8UC3 sRGB or CV_32FC3 linear HDR, BGR, any size (they may differ per face). A
// missing face (an empty Mat: its renderer was late, its camera dropped out) keeps showing the
// last image presented for it with its last crop, never black; a face never given stays black. Linear faces
// are multiplied by config.exposure, clamped to [0, 1] (NaN shows black, +Inf white) and sRGB-encoded on the
// GPU; tone mapping is the renderer's job.
#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "holo/display/layout.hpp"

namespace holo::display {

using FaceImages = std::array<cv::Mat, kFaceCount>;

class QuadViewPresenter {
 public:
  virtual ~QuadViewPresenter() = default;
  // Shows one quad frame. `coverage` (optional, CV_8UC1 per face, empty entries allowed) gives
  // the object masks for auto-fit; without it auto-fit uses the non-black pixels.
  virtual void present(const FaceImages& face_images, const FaceImages* coverage = nullptr) = 0;
  // The last presented frame as CV_8UC3 BGR (black before the first present()).
  virtual cv::Mat readBack() = 0;
  // False once a window was closed or Escape pressed; always true headless. Polls events.
  virtual bool isOpen() = 0;
  virtual const DisplayConfig& config() const = 0;
  // Pixels of output `output` (0 .. outputCount - 1): a fullscreen window's, its monitor's mode;
  // otherwise config().output_size.
  virtual cv::Size outputSize(int /*output*/) const { return config().output_size; }
  // Crop rectangles (face image pixels) used for the last frame; the whole image without
  // auto-fit; an empty rectangle for a face never given.
  virtual const std::array<cv::Rect2f, kFaceCount>& lastCrops() const = 0;
  // Ends the session: a recording presenter closes its video (renames it into place). Call once
  // after the last present(); without it an unfinished recording is discarded.
  virtual void finish() {}
};

// The side in pixels at which to render square face images for `presenter`'s screen: the largest
// face as placed on its output (faceViewPixels, layout.hpp), over the outputs.
int screenFaceViewPixels(const QuadViewPresenter& presenter);

// Throws holo::Error with EGL's reason when no OpenGL 3.3 core context can be made.
std::unique_ptr<QuadViewPresenter> makeHeadlessPresenter(const DisplayConfig& config);
// Throws holo::Error when GLFW cannot start (no X display) and holo::InputError when a face's
// monitor is not connected (naming the field display.faces[N].monitor of config.source).
std::unique_ptr<QuadViewPresenter> makeWindowPresenter(const DisplayConfig& config);

// Headless output of a run: what every present() showed, read back and written to disk.
struct RecordingSettings {
  std::filesystem::path out_dir;            // created when missing
  std::string video_name = "quadview.mp4";  // empty: no video
  double fps = 30.0;                        // of the video
  int png_every = 0;                        // write frame_NNNNN.png every this many frames; 0: none
};
// Wraps `inner` (usually the headless presenter): after each present() the canvas is read back
// and appended to the MP4 (VideoFileWriter, atomic at finish()) and, every png_every frames
// (starting with frame 0), written as a PNG (atomically).
std::unique_ptr<QuadViewPresenter> makeRecordingPresenter(std::unique_ptr<QuadViewPresenter> inner,
                                                          const RecordingSettings& settings);

}  // namespace holo::display
