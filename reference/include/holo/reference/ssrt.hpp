// Evaluation only: a reference for measuring the appliance's renderer, never linked by it
// (reference/CMakeLists.txt).
// The screen-space ray tracing baseline (SSRT) of the paper's Figure 7 comparison (McGuire and
// Mara 2014, as the paper uses it): the depth cameras' RGBD images are reprojected into one RGBD
// image seen from the pyramid origin O, and reflected rays are marched against that image alone.
//
// What SSRT sees (pinned down from the paper, Sec. 4.1.1): a 360-degree equirectangular RGBD map
// centred on O (a perspective camera at O cannot see all four sides), filled by reprojecting
// every foreground point (the RGBD pixels back-projected: the same ForegroundCloud ours bins);
// where several points land on one map pixel only the nearest to O is kept and the rest are
// discarded, so the map has holes and hides what is behind the nearest surface, exactly the two
// losses the paper names. The static hall comes from the same prefiltered IBL as ours (a ray that
// finds nothing in the map falls back to it, as screen-space reflections fall back to a probe).
//
// Per relic hit point (the same hit points and 4-sample anti-aliasing as ours), `rays` directions
// are drawn from the GGX visible-normal distribution (the mirror direction when roughness < 0.01),
// seeded per pixel; each is marched from the hit point in `steps` uniform steps (jittered) over
// max_distance, a step hitting when its distance from O lies within [d, d + thickness] of the
// map's depth d along its direction, refined by bisection. psi_d is the mean radiance of the rays
// that hit and w their fraction; psi_f = psi_d w + psi_s (1 - w) with the split-sum specular scale,
// plus the SH diffuse, as in ours. Few rays on a glossy relic give the paper's "noisy points".
// Units: metres (world = pyramid frame), linear radiance; images CV_32FC3 linear BGR.
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

#include "holo/core/camera_model.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::reference {

struct SsrtSettings {
  vec3 origin{0.0f};          // O, where the reprojected RGBD image is seen from (metres)
  int map_width = 1024;       // equirectangular RGBD map, pixels (height = width / 2)
  int rays = 1;               // reflected rays per hit point, >= 1
  int steps = 64;             // march steps per ray, >= 1
  int refine_steps = 4;       // bisection steps after a hit, >= 0
  int aa_samples = 4;         // hit points per pixel: 1 or 4 (as ours)
  float max_distance = 3.0f;  // metres a reflected ray is marched
  float thickness = 0.25f;    // metres behind the map's depth still counted as a hit
  float ray_offset = 1e-3f;   // metres along the normal, against self-intersection
  std::uint64_t seed = 1;
  // Throws InputError naming the field.
  void validate() const;
};

// The foreground reprojected into one equirectangular RGBD image at O (nearest point wins).
class ReprojectedRgbd {
 public:
  ReprojectedRgbd(const depthfilter::ForegroundCloud& cloud, const vec3& origin, int width);
  // Distance from O (metres) stored at the pixel of `direction`; 0 where nothing landed.
  float depthAlong(const vec3& direction, int* pixel) const;
  vec3 radiance(int pixel) const { return radiance_[std::size_t(pixel)]; }
  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t filledPixels() const { return filled_; }

 private:
  vec3 origin_;
  int width_ = 0, height_ = 0;
  std::vector<float> depth_;
  std::vector<vec3> radiance_;
  std::size_t filled_ = 0;
};

struct SsrtStats {
  std::uint64_t rays = 0, hits = 0;
  std::size_t filled_pixels = 0;  // map pixels holding a point
};

// Renders one view with SSRT. `scene` holds the relic (emitters are ignored); `ibl` the static
// environment. Throws InputError on invalid settings.
cv::Mat renderSsrt(const reflect::RenderScene& scene, const reflect::PrefilteredIbl& ibl,
                   const depthfilter::ForegroundCloud& cloud, const CameraModel& view,
                   const SsrtSettings& settings, SsrtStats* stats = nullptr);

}  // namespace holo::reference
