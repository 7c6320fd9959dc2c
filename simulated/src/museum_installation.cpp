#include "holo/simulated/museum_installation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/fibonacci_sphere.hpp"
#include "holo/core/log.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/sim/halls.hpp"
#include "holo/sim/museum.hpp"
#include "holo/simulated/simulated_source.hpp"

namespace holo::simulated {
namespace {

// The hall's mean distance from `centre` over a Fibonacci sphere of directions (metres), those
// that meet the pyramid's base (half width `base_half_width`, top at y = 0) first left out: the
// radius of the sphere the panorama captured there is placed on. Infinite when no direction
// meets the hall.
float meanHallDistance(const Model& hall, const vec3& centre, float base_half_width) {
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  if (hall.meshes.empty()) return kInfinity;
  const reflect::RenderScene scene(Model{}, {hall});
  // With no sphere, the proxy's point for a direction is finite only where the base hides the hall.
  const reflect::PanoramaProxy base_only{centre, kInfinity, base_half_width};
  constexpr int kDirections = 4096;
  double sum = 0.0;
  int hits = 0;
  for (int i = 0; i < kDirections; ++i) {
    const vec3 direction = fibonacciDirection(i, kDirections);
    if (isFinite(base_only.point(direction))) continue;
    const RayHit hit = scene.all().intersect(Ray{centre, direction});
    if (!hit.hit()) continue;
    sum += double(hit.t);
    ++hits;
  }
  return hits > 0 ? float(sum / double(hits)) : kInfinity;
}

}  // namespace

reflect::PanoramaProxy museumPanoramaProxy(const sim::Museum& museum) {
  const vec3 centre = museum.description().panorama_position;
  const float radius = meanHallDistance(museum.hall(), centre, sim::kBaseHalfWidth);
  if (!std::isfinite(radius)) return {};
  return {centre, radius, sim::kBaseHalfWidth};
}

pipeline::Installation museumInstallation(const std::string& scene, bool paced, int panorama_width,
                                          const std::string& relic) {
  sim::SceneDescription description = sim::loadScene(scene);
  if (!relic.empty()) description.relic = relic;
  auto museum = std::make_shared<const sim::Museum>(std::move(description));
  pipeline::Installation installation;
  installation.name = "scene " + museum->description().name;
  const int n = museum->cameraCount();
  installation.background.resize(static_cast<std::size_t>(n));
  tbb::parallel_for(0, n, [&](int i) {
    installation.background[static_cast<std::size_t>(i)] = museum->backgroundFrame(i);
  });
  for (int i = 0; i < n; ++i) {
    installation.sources.push_back(
        std::make_unique<SimulatedSource>(museum, i, SimulationOptions{.paced = paced}));
    installation.cameras.push_back(museum->camera(i));
    capture::CaptureOptions options;
    options.camera_id = i;
    installation.capture_options.push_back(options);
  }
  installation.check_sources.push_back(std::make_unique<SimulatedSource>(museum, sim::Museum::kCheckCamera,
                                                                         SimulationOptions{.paced = paced}));
  installation.check_cameras.push_back(museum->camera(sim::Museum::kCheckCamera));
  installation.simulated_cameras = true;
  installation.camera_exposure = museum->description().camera.exposure;
  installation.fps = museum->description().camera.fps;
  installation.relic = museum->relic();
  installation.plinth = museum->description().plinth;
  const int pw = std::max(64, panorama_width);
  installation.panorama = museum->renderPanorama(pw, pw / 2);
  installation.panorama_proxy = museumPanoramaProxy(*museum);
  if (!installation.panorama_proxy.infinite())
    HOLO_LOG_INFO(
        "panorama on the hall's mean distance {:.2f} m around its capture point, above a base of half "
        "width {:.2f} m",
        installation.panorama_proxy.radius, installation.panorama_proxy.base_half_width);
  return installation;
}

pipeline::Installation installationFor(const pipeline::FrameLoopOptions& options) {
  if (options.config.empty())
    return museumInstallation(options.scene, options.live, options.panorama_width, options.relic);
  const ConfigNode root = ConfigNode::loadFile(options.config);
  if (!pipeline::describesCameras(root))
    throw InputError(options.config, "capture",
                     "a capture: section naming the cameras (and an exhibit: section naming the relic and "
                     "panorama) to run on them");
  return pipeline::loadInstallation(root, {.simulated_sources = configuredSources()});
}

}  // namespace holo::simulated
