// Evaluation only: a reference for measuring the appliance's renderer, never linked by it
// (reference/CMakeLists.txt).
// Caustics of a transmissive relic on a diffuse receiver under a small bright light, by photon
// tracing (Kán's thesis, "caustics of refractive objects by photon mapping"): the light the relic
// focuses onto the receiver, which the path tracer (path_tracer.hpp), gathering from the camera
// and reaching lights by BSDF sampling only, cannot find through delta glass from a point light.
//
// Photons leave a point light of power `power` (W per RGB channel, isotropic) towards the relic's
// bounding sphere only (the cone it subtends; the whole sphere of directions when the light is
// inside it), each carrying power x (cone solid angle / 4 pi) / photon count. A photon scatters
// on the relic's glTF BSDF (dielectric.hpp's MaterialBsdf, media and Beer-Lambert absorption as
// the path tracer) up to max_scatterings times and is kept where it then meets the receiver
// within its square: only light that reached the receiver through the relic (L (relic)+ D), so
// a photon that misses the relic (the receiver's direct light) is never traced. The relic's
// refraction weights carry (n_o / n_i)^2 per crossing for radiance; a photon on the receiver is
// in air, so the factors of its entries and exits cancel. Shading normals scatter photons as
// they scatter paths (no adjoint correction): on a finely tessellated smooth relic the two agree.
//
// Two estimates of the receiver's caustic irradiance (W/m^2 per RGB channel) on a grid over its
// square, from the same photons' kind:
//  - the photon map: a density estimate with the Epanechnikov kernel of a fixed radius
//    (biased by its blur, low noise from few photons: the renderer);
//  - the light tracer: each photon binned into the grid cell it lands in (unbiased cell
//    averages; converged with many photons: the reference the photon map is measured against).
// Photon i uses sample index i of one Owen-scrambled Sobol stream (sampler.hpp): results depend
// only on the seed and the photon count, whatever the thread count.
//
// Which relics run it (the caustic plan, planCaustics): a relic with a transmissive material
// (transmission > 0) wholly above the receiver, with the light above the receiver too. Anything
// else, an opaque relic first, traces no photon: the counters "Caustics/Photons traced" and
// "Caustics/Photons stored" stay at zero.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "holo/core/math.hpp"
#include "holo/reflect/render_scene.hpp"

namespace holo::reference {

// A horizontal diffuse receiver at y = height (the pyramid base or a plinth under the relic),
// lit from above: the square centre +- half_size in x and z (metres).
struct CausticReceiver {
  float height = 0.0f;
  vec2 centre{0.0f};  // (x, z)
  float half_size = 0.1f;
};

struct PointLight {
  vec3 position{0.0f, 1.0f, 0.0f};  // metres
  vec3 power{1.0f};                 // W per RGB channel, emitted isotropically
};

struct CausticPlan {
  bool runs = false;
  std::string reason;  // why it runs or not, for the log and --stats
};
CausticPlan planCaustics(const reflect::RenderScene& scene, const CausticReceiver& receiver,
                         const PointLight& light);

struct Photon {
  vec2 position;  // (x, z) on the receiver, metres
  vec3 power;     // W per RGB channel
};

struct PhotonTracingOptions {
  std::uint64_t seed = 1;
  int max_scatterings = 32;  // relic scatterings per photon (total internal reflections count)
};

// Traces photons [first, first + count) of the stream and returns those kept on the receiver,
// in photon order. Every photon's power is divided by `total_count` (the photons of the whole
// estimate, >= first + count). Returns nothing, tracing nothing, when planCaustics says no.
std::vector<Photon> tracePhotons(const reflect::RenderScene& scene, const CausticReceiver& receiver,
                                 const PointLight& light, std::uint64_t first, std::uint64_t count,
                                 std::uint64_t total_count, const PhotonTracingOptions& options = {});

// Irradiance on the receiver's square, `resolution` x `resolution` cells (row = z, column = x,
// both increasing), CV_32FC3 BGR in W/m^2. cellCentre gives a cell's (x, z).
struct ReceiverImage {
  CausticReceiver receiver;
  int resolution = 0;
  cv::Mat irradiance;
  float cellSize() const { return 2.0f * receiver.half_size / float(resolution); }
  vec2 cellCentre(int column, int row) const;
};

// The photon map's density estimate with kernel radius `radius` (metres, > 0).
ReceiverImage photonMapEstimate(const std::vector<Photon>& photons, const CausticReceiver& receiver,
                                int resolution, float radius);
// The light tracer: photons binned into cells; call addPhotons with every batch, in order.
class LightTracerImage {
 public:
  LightTracerImage(const CausticReceiver& receiver, int resolution);
  void addPhotons(const std::vector<Photon>& photons);
  ReceiverImage image() const;

 private:
  CausticReceiver receiver_;
  int resolution_;
  std::vector<glm::dvec3> power_;  // W per cell
};

// The caustic's peak on the receiver: the irradiance-weighted centroid (luminance) of the cells
// within `window` metres of the brightest cell of the image box-filtered over 3x3 cells; and
// its energy: the power (W, luminance) on the cells within `radius` metres of `centre`.
vec2 causticPeak(const ReceiverImage& image, float window);
double causticPower(const ReceiverImage& image, const vec2& centre, float radius);

}  // namespace holo::reference
