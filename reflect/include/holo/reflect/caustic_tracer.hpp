// The live light tracer of a transmissive relic's caustic: photons from the light sources through
// the relic's glass onto a horizontal diffuse receiver (the plinth's top), binned into a grid of
// the receiver's irradiance. The appliance's own mechanism (the evaluation's photon tracer,
// reference/caustics.hpp, is its measure and is never linked here).
//
// Two sources:
//  - the hall (traceEnvironmentCaustics): directions drawn from the prefiltered IBL's sharpest
//    level in proportion to radiance times texel solid angle (its bright lamps and windows first),
//    each photon entering a disc across the relic's bounding sphere, perpendicular to its
//    direction, with flux L(w) pi r^2 / (pdf(w) N). The relic's turn (PrefilteredIbl::relicTurn)
//    turns the hall about the relic as every other lookup does. Or, for a path tracer that lights
//    its scene with an Environment (the AR composite), the directions that Environment samples
//    (its panorama at infinity, per pixel), the same disc and flux;
//  - a point light (tracePointCaustics, power W per RGB channel, isotropic): photons in the cone
//    the bounding sphere subtends, each with power (cone share of the sphere) / N.
// A photon follows the relic as delta scattering on smooth interfaces (roughness is not widened):
// at each hit the exact Fresnel reflectance F of its IOR (optics.hpp) chooses reflection (prob. F,
// total internal reflection always) or transmission, weighted by (1 - metallic) transmission
// base_colour when it enters; what is neither (the diffuse base) ends the photon; Beer-Lambert
// absorption inside a volume (thickness > 0; a thin-walled material passes light unbent). After
// at least one relic event, a photon that reaches the receiver's plane from above within its
// square adds its flux to the cell it lands in (the light tracer's estimate: unbiased cell means).
// Photons that miss the relic are the receiver's direct light and are not traced. The grid is
// then smoothed by a tent of `smoothing_cells` (0: none). Deterministic per seed: photon i draws
// from a hash of (seed, i) and batches are summed in a fixed order, whatever the threads.
// Units: metres, W, W/m^2; images CV_32FC3 BGR, row = z, column = x (both increasing).
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

#include "holo/core/math.hpp"
#include "holo/reflect/environment.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::reflect {

struct CausticReceiverGrid {
  vec2 centre{0.0f};  // (x, z) of the square's centre
  float half_size = 0.1f;
  float height = 0.0f;   // y of the receiving plane; light arrives from above
  int resolution = 128;  // cells along a side
  float cellSize() const { return 2.0f * half_size / float(resolution); }
};

struct CausticTracerSettings {
  std::uint64_t photons = 1u << 20;  // launched
  std::uint64_t seed = 1;
  int max_events = 16;      // relic interface events per photon
  int smoothing_cells = 1;  // tent radius in cells over the binned grid
};

struct CausticImage {
  CausticReceiverGrid grid;
  cv::Mat irradiance;        // W/m^2 per BGR channel, resolution^2
  std::uint64_t traced = 0;  // photons launched
  std::uint64_t stored = 0;  // photons that reached the receiver through the relic
  double ms = 0.0;           // wall time of the trace
};

// Some relic material lets light through (transmission > 0, or an override that does).
bool relicTransmits(const RenderScene& scene);

CausticImage traceEnvironmentCaustics(const RenderScene& scene, const PrefilteredIbl& ibl,
                                      const CausticReceiverGrid& grid, const CausticTracerSettings& settings);
CausticImage traceEnvironmentCaustics(const RenderScene& scene, const Environment& environment,
                                      const CausticReceiverGrid& grid, const CausticTracerSettings& settings);
CausticImage tracePointCaustics(const RenderScene& scene, const vec3& light_position, const vec3& light_power,
                                const CausticReceiverGrid& grid, const CausticTracerSettings& settings);

}  // namespace holo::reflect
