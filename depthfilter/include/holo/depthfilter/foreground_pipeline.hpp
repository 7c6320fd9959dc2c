// The foreground point cloud of all cameras, every frame (paper Sec. 3.2, docs/architecture.md): per
// camera, in parallel (oneTBB), the foreground mask phi_i, the precursor flow lambda_i and the
// mask's persistence where the sensor reads nothing; then, across the cameras, each camera's holes
// on a visitor filled with the depth another camera measured of it (cross_camera_fill.hpp); then
// per camera again the pull-push temporal depth filter (a hole beside two surfaces of its colour
// decided by the other cameras' measured depth, other_camera_witness.hpp) and the border
// expansion; then every filtered foreground pixel is back-projected into the world (pyramid) frame with that
// camera's CameraModel, its sRGB colour linearised, multiplied by the camera's colour gains and divided by
// the exposure, its source (camera, pixel) kept.
//
// With `scale` 2 every per-camera stage runs on the frames reduced to half width and height
// (foreground_scale.hpp); the points keep the camera's own pixel coordinates. With
// full_size_outline the reduced foreground's outline is redrawn from the camera's own depth
// (full_size_outline.hpp) and its points come from the camera's pixels.
//
// A camera whose frame is missing (empty RgbdFrame) contributes nothing this frame and its
// filter forgets its history (counted as "Depthfilter/Missing camera frames").
// Invariant: every point of the cloud is finite, weight in (0, 1], pixel inside its camera.
#pragma once

#include <span>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/core/rgbd_frame.hpp"
#include "holo/depthfilter/border_expansion.hpp"
#include "holo/depthfilter/cross_camera_fill.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"
#include "holo/depthfilter/foreground_mask.hpp"
#include "holo/depthfilter/foreground_scale.hpp"
#include "holo/depthfilter/mask_persistence.hpp"
#include "holo/depthfilter/other_camera_witness.hpp"
#include "holo/depthfilter/precursor_flow.hpp"
#include "holo/depthfilter/temporal_depth_filter.hpp"

namespace holo::depthfilter {

struct ForegroundPipelineConfig {
  ForegroundMaskConfig mask;
  std::vector<cv::Mat> static_foreground;  // per camera (may be shorter or hold empty Mats)
  PrecursorFlowConfig flow;
  MaskPersistenceConfig persistence;
  CrossCameraFillConfig cross_camera;
  TemporalDepthFilterConfig filter;
  BorderExpansionConfig border;
  float exposure = 1.0f;  // radiance = srgbToLinear(colour) / exposure (the camera's exposure)
  // Per camera, linear RGB multipliers that match its colours to the other cameras' (the
  // calibration's colour gains); missing entries are 1.
  std::vector<vec3> colour_gains;
  bool parallel = true;  // cameras in parallel with oneTBB
  // The foreground's resolution: the camera's divided by this, 1..kMaxForegroundScale
  // (foreground_scale.hpp); every pixel setting above counts the reduced frames' pixels.
  int scale = kDefaultForegroundScale;
  // With a scale above 1: the mask, the depth, the border and the points at the camera's
  // resolution, the outline decided by the camera's own depth readings (full_size_outline.hpp),
  // everything else still at the reduced one.
  bool full_size_outline = false;
};

// What one camera produced in the last frame (for the reflection stage's pyramids and for tests), at
// the foreground's resolution (the camera's divided by ForegroundPipelineConfig::scale); with
// ForegroundPipelineConfig::full_size_outline the mask, depth and border at the camera's.
struct CameraForeground {
  cv::Mat mask;          // CV_8UC1, 255 = foreground
  cv::Mat flow;          // CV_32FC2, current -> previous, guaranteed on the mask's box and the
                         // persistence's search box only (nothing reads it elsewhere; see next())
  cv::Mat depth;         // CV_32FC1 filtered foreground depth, 0 elsewhere
  BorderLayer border;    // expanded border
  bool present = false;  // false when the camera's frame was missing
};

class ForegroundPipeline {
 public:
  // One CameraModel per camera; frames are matched to cameras by their index in the span.
  // Throws holo::Error when `cameras` is empty, exposure is not positive or the scale is out of
  // range or does not divide a camera's size.
  explicit ForegroundPipeline(std::vector<CameraModel> cameras, ForegroundPipelineConfig config = {});
  ~ForegroundPipeline();
  ForegroundPipeline(ForegroundPipeline&&) noexcept;
  ForegroundPipeline& operator=(ForegroundPipeline&&) noexcept;

  // Background frames gamma_s, one per camera (empty frames are skipped).
  void learnBackground(std::span<const RgbdFrame> frames);
  // Forgets every camera's background (both models) and its frame history, as if newly made:
  // learnBackground starts from nothing (the technician's "relearn the background").
  void forgetBackground();
  // One live frame per camera -> the foreground cloud. Throws holo::Error when the span's size
  // differs from the number of cameras or a frame's size differs from its camera's.
  ForegroundCloud process(std::span<const RgbdFrame> frames);

  std::size_t cameraCount() const;
  const CameraForeground& lastResult(std::size_t camera) const;
  const TemporalDepthFilter& filter(std::size_t camera) const;

 private:
  struct CameraStage;
  ForegroundPipelineConfig config_;
  std::vector<CameraModel> cameras_;                    // as the foreground's frames see them (reducedCamera)
  std::vector<CameraModel> camera_resolution_cameras_;  // as given
  std::vector<CameraStage> stages_;
  CrossCameraFill cross_camera_;
  OtherCameraWitnesses witnesses_;  // the other cameras decide the filter's two-surface holes
};

}  // namespace holo::depthfilter
