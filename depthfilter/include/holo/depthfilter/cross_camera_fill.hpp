// The cameras fill each other's holes (paper Sec. 3.2 runs one filter per camera; four cameras
// surround the pyramid and see most visitors twice). Where camera B's sensor reads nothing on a
// visitor (beyond its range, at a grazing angle, in the projector's shadow), the depth another
// camera A measured of the same visitor is projected through the calibrated poses into B:
//   * sources: A's foreground pixels with measured depth whose four neighbours were measured on
//     the same surface (|difference| <= tolerance(z)): a silhouette's mixed pixels are not sent;
//     the surface's normal (from those neighbours) must face B: a side B cannot see is not sent;
//   * each source point is splatted into B as a square as wide as its footprint there (1 to
//     max_splat_px pixels); per pixel the nearest surface wins (a z-buffer over all sources) and
//     its depth is the mean of the points on it (within tolerance(z) of the nearest);
//   * a projected point fills B's pixel only where B's sensor read nothing, where it lies in front
//     of B's learned background depth by more than tolerance(z) (the hall's walls and anything
//     standing in them hide it), and where no valid depth of B's own within visibility_radius_px
//     is nearer than it by more than tolerance(z) (a visitor behind a pillar, a torso behind an
//     arm B does see). The pixel becomes foreground: the mask's recall where the sensor reads
//     nothing, and the filter downstream treats the fill as a measurement;
//   * where B did read depth and it agrees with the projected visitor within tolerance(z) and
//     lies in front of B's background, the pixel joins B's mask (thin limbs the mask's opening
//     removed), its depth B's own.
// Sources are the masks as they arrive: a pixel one camera received is never passed on.
// tolerance(z) = tolerance_m + tolerance_z2 * z^2 (metres), like depth-sensor noise.
//
// Units: metres, pixels. Invariants: a measured depth is never changed; a mask only grows; a
// filled pixel's depth is another camera's measurement of a point B's pose can see.
#pragma once

#include <span>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"

namespace holo::depthfilter {

struct CrossCameraFillConfig {
  // Off by default: on the five simulated halls it raises the coverage everywhere but makes ours
  // less steady on two (docs/depthfilter.md, "Cameras filling each other").
  bool enabled = false;
  float tolerance_m = 0.04f;     // constant part of tolerance(z), metres
  float tolerance_z2 = 0.0075f;  // grows with z^2, 1/metres
  int visibility_radius_px = 2;  // B's own nearer depth within this many pixels hides a fill
  int max_splat_px = 3;          // widest square one source point covers in B
  bool confirm_measured = true;  // B's agreeing measured depth joins B's mask
};

// One camera's frame as the cross-camera step sees it. Mats share their data with the caller's.
struct CrossCameraView {
  cv::Mat depth;             // CV_32FC1 measured depth (0/NaN/Inf = none); empty: camera missing
  cv::Mat mask;              // CV_8UC1, 255 = foreground; grown in place
  cv::Mat background_depth;  // CV_32FC1 the hall's learned depth, 0 = unknown; empty = unknown
};

struct CrossCameraCounts {
  long filled = 0;     // holes given another camera's depth
  long confirmed = 0;  // measured pixels added to the mask
};

class CrossCameraFill {
 public:
  // One CameraModel per camera, in the order of the views. Throws holo::Error when a setting is
  // out of range (tolerance_m in [0.001, 0.5], tolerance_z2 in [0, 0.1], visibility_radius_px in
  // [0, 8], max_splat_px in [1, 8]).
  explicit CrossCameraFill(std::vector<CameraModel> cameras, CrossCameraFillConfig config = {});

  // Grows every present view's mask in place and returns per camera the depth to filter: the
  // measured depth with the filled holes (a new Mat), or the view's own depth where nothing was
  // filled or the step is disabled (an empty Mat for a missing camera). counts, when given, gets
  // one entry per camera. Throws holo::Error when the number of views or a view's size or type
  // does not match its camera.
  std::vector<cv::Mat> apply(std::span<CrossCameraView> views,
                             std::vector<CrossCameraCounts>* counts = nullptr) const;

  const CrossCameraFillConfig& config() const { return config_; }

 private:
  std::vector<CameraModel> cameras_;
  std::vector<std::vector<vec3>> plane_directions_;  // per camera, z = 1 ray per pixel, row-major
  CrossCameraFillConfig config_;
};

}  // namespace holo::depthfilter
