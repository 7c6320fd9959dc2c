// The other cameras as witnesses of one camera's holes (SurfaceWitness). Where camera B's filter
// cannot tell which of two surfaces of one colour a hole shows (an arm in front of the torso,
// two legs), B's pixel is back-projected at each candidate depth and looked up in every other
// camera A's measured depth of the same frame:
//   * Seen: A measured, on its foreground mask, a depth within tolerance(z) of the point's depth
//     in A: a visitor's surface is there;
//   * Empty: A measured a depth beyond the point by more than tolerance(z): A sees through it;
//   * otherwise (outside A's image, behind A, A read nothing, something nearer hides it from A)
//     A says nothing. The cameras' answers combine: Seen by some and Empty by none is Seen,
//     Empty by some and Seen by none is Empty, anything else Unknown.
// tolerance(z) = tolerance_m + tolerance_z2 * z^2 (metres), the cross-camera fill's.
// Cost: a transform, a projection and a read per hole candidate and other camera: the few
// hundred holes per frame that reach it, not the images.
//
// Units: metres, pixels. Invariant: answers read only the measured depth and masks of the frame
// given; a missing camera (empty depth) says nothing.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"
#include "holo/depthfilter/cross_camera_fill.hpp"
#include "holo/depthfilter/surface_witness.hpp"

namespace holo::depthfilter {

class OtherCameraWitnesses;

// The witness for one camera of one frame; refers to the views and the witnesses it came from.
class OtherCameraWitness final : public SurfaceWitness {
 public:
  Sighting sighting(int x, int y, float depth) const override;

 private:
  friend class OtherCameraWitnesses;
  OtherCameraWitness(const OtherCameraWitnesses& witnesses, std::span<const CrossCameraView> views,
                     std::size_t target)
      : witnesses_(&witnesses), views_(views), target_(target) {}
  const OtherCameraWitnesses* witnesses_;
  std::span<const CrossCameraView> views_;
  std::size_t target_;
};

class OtherCameraWitnesses {
 public:
  // One CameraModel per camera, in the order of the views; tolerances as CrossCameraFillConfig's
  // (its ranges, checked there: tolerance_m in [0.001, 0.5], tolerance_z2 in [0, 0.1]; throws
  // holo::Error otherwise).
  OtherCameraWitnesses(std::vector<CameraModel> cameras,
                       float tolerance_m = CrossCameraFillConfig{}.tolerance_m,
                       float tolerance_z2 = CrossCameraFillConfig{}.tolerance_z2);

  // The witness of camera `target`'s holes by the other views (their depth and mask; the
  // background is not read). The views must outlive it and match the cameras (holo::Error).
  OtherCameraWitness witnessFor(std::span<const CrossCameraView> views, std::size_t target) const;

  std::size_t cameraCount() const { return cameras_.size(); }

 private:
  friend class OtherCameraWitness;
  std::vector<CameraModel> cameras_;
  std::vector<std::vector<vec3>> plane_directions_;  // per camera, z = 1 ray per pixel, row-major
  std::vector<std::vector<mat4>> a_from_b_;          // [b][a]: camera b's frame -> camera a's
  float tolerance_m_;
  float tolerance_z2_;
};

}  // namespace holo::depthfilter
