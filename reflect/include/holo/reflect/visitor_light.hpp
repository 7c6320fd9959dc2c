// Visitors in the hall's light: the visitors near the relic hide part of the hall from it (a
// visitor between a bright window and the relic shadows it) and light it with their own radiance.
// The static shading lights the relic's diffuse and widest lobes from the empty hall; this adds,
// per frame, the change the visitors make to that light.
//
// Per frame (build): from each of eight probes at the corners of the relic's box, every occupied
// voxel of the foreground grid is splatted into a small equirectangular map as a disc of one voxel
// edge's angular radius, the nearest voxel winning each texel (as RoughForegroundMap): its
// radiance and mask weight w. Over the covered texels the change of the incoming radiance,
// dL = w (L_visitor - L_hall), L_hall the IBL seen from the probe through the hall's proxy, is
// projected on the 9 real spherical harmonics of bands 0-2 (irradiance_sh.hpp's basis; each
// texel its exact solid angle). Per pixel (apply): the probes' coefficients interpolated
// trilinearly at its first valid hit point give each sample's irradiance change
// dE(n) = sum_i kCosineLobe_i c_i Y_i(n) (Ramamoorthi & Hanrahan's clamped-cosine convolution). The diffuse
// part gains rho_eff dE(n), rho_eff = diffuse / E_hall(n) per channel (at most 1 / pi): the material's
// diffuse reflectance times the share of the hall's light the relic's own visibility let through,
// so the visitors' light is self-occluded as the hall's is. A material at least
// kGlossyRoughnessLimit rough (no voxel walk reads the visitors for it) also gains
// specular_scale dE(r) / pi around its reflected direction r: the cosine lobe stands for a lobe
// that wide. A pixel never goes below zero.
// Parallax between the probes is linear; the relic shadows the visitors' light only through the
// visibility share above. Units: metres, linear radiance, irradiance in radiance x sr.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/core/math.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/voxel_grid.hpp"

namespace holo::reflect {

class VisitorLight {
 public:
  // Probe maps of map_width x map_width / 2 texels (even, 8..1024; throws InputError otherwise).
  explicit VisitorLight(int map_width = 64);

  // This frame's light change from the grid's visitors around `relic_bounds` (an empty grid or
  // box: no change anywhere).
  void build(const VoxelGrid& grid, const PrefilteredIbl& ibl, const Bounds3& relic_bounds);

  // The irradiance change dE at a point (clamped into the probes' box) for a unit normal.
  vec3 irradianceChange(const vec3& position, const vec3& normal) const;

  // What a view's static shading fixes of each covered pixel's response to the change. A pixel's
  // change is linear in the 9 coefficients interpolated at one point (its first valid sample: the
  // probes' light changes over metres), so its samples fold into one response per pixel: per
  // coefficient i and channel, the mean over the pixel's samples of rho_eff kCosineLobe_i Y_i(n),
  // plus specular_scale kCosineLobe_i Y_i(r) / pi for a material at least kGlossyRoughnessLimit
  // rough (invalid samples count in the mean as zero, as they do in the pixel). They depend on the
  // hit points and static shading only, not on the visitors, so a view whose static shading is
  // reused reuses them (frame_renderer.hpp's view cache) and each frame pays per pixel one
  // trilinear interpolation of the probes and one 27-term sum.
  // [3 i + channel] (channels RGB), then one zero: whole SIMD vectors for the per-pixel sums.
  using Response = std::array<float, 28>;
  struct Receivers {
    std::vector<std::uint32_t> pixels;  // hits.covered's pixels (y * width + x)
    std::vector<vec3> positions;        // per pixel: where its probes are read
    std::vector<Response> responses;    // per pixel
    std::uint64_t samples = 0;          // the valid samples they stand for
  };
  // The receivers of `hits` shaded `shading` under the hall `ibl`; independent of any frame's
  // visitors (callable before build()).
  static Receivers receivers(const HitPointBuffer& hits, const std::vector<SplitSumShading>& shading,
                             const PrefilteredIbl& ibl);

  // Adds each covered pixel's change to hdr (view-sized CV_32FC3 linear BGR, the frame's image so
  // far), clamping the pixel at 0. `receivers` are receivers() of the same hits and shading. With
  // `display` (view-sized CV_8UC3, hdr's tone-mapped image at `exposure`), each changed pixel's
  // displayed code is written too (toneMapPixel), so nothing else need tone-map the view again.
  // Returns the samples changed.
  std::uint64_t apply(const Receivers& receivers, int width, cv::Mat& hdr, cv::Mat* display = nullptr,
                      float exposure = 0.0f) const;

  // The most the grid's visitors can change a relic pixel this frame (linear radiance, any
  // channel), without a splat: what the effect plan weighs before build() runs. Each occupied
  // voxel (mask weight w, radiance L) covers at most the probes' disc, of one voxel edge's angular
  // radius, seen from the nearest point of the relic's box; there the incoming radiance changes
  // by |w (L - L_hall)| <= w max(L, L_hall), L_hall at most `brightest_hall` (per channel, the
  // IBL's brightest()). The clamped-cosine convolution of such a change is at most cosinePeak()
  // times its integral over the voxels' discs, and at most the kernel's own integral over the
  // sphere (pi in front of the normal, a little ringing behind) times its largest value; a pixel
  // takes at most 1/pi of the irradiance change through its diffuse part, as much again through a
  // lobe at least kGlossyRoughnessLimit rough (`wide_lobes`). One pass over the occupied voxels.
  static float largestRadianceChange(const VoxelGrid& grid, const Bounds3& relic_bounds,
                                     const vec3& brightest_hall, bool wide_lobes);
  // The irradiance the clamped-cosine convolution of bands 0-2 gives a normal from a unit of
  // radiance x solid angle along it: sum over the bands of A_l (2l + 1) / (4 pi) = 1.0625, its
  // largest magnitude over all directions.
  static float cosinePeak();

  // This frame's counters: voxel splats over all probes, covered texels over all probes.
  std::uint64_t splats() const { return splats_; }
  std::uint64_t coveredTexels() const { return covered_texels_; }
  int mapWidth() const { return width_; }

  static constexpr int kProbes = 8;

 private:
  using Coefficients = std::array<vec3, 9>;
  Coefficients coefficientsAt(const vec3& position) const;
  // The change of a pixel of response `response` read at `position`, per channel (RGB).
  vec3 responseChange(const vec3& position, const Response& response) const;

  int width_ = 0, height_ = 0;
  std::vector<vec3> direction_;     // per texel, unit, its centre
  std::vector<float> solid_angle_;  // per texel, sr
  Bounds3 box_;                     // the probes' box
  // Per probe its 9 coefficients as [3 i + channel] (channels RGB), then one zero, as Response.
  std::array<Response, kProbes> coefficients_{};
  bool empty_ = true;
  std::uint64_t splats_ = 0, covered_texels_ = 0;
};

}  // namespace holo::reflect
