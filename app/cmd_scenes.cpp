// `holopyramid scenes [NAME|FILE]`: without an argument, the built-in scene names one per line,
// then `relics:` and the built-in relic names; with one, what that scene contains.
#include <iostream>

#include "command.hpp"
#include "holo/sim/museum.hpp"

namespace holo::app {
namespace {

int listScenes() {
  for (const auto& name : sim::builtinSceneNames()) std::cout << name << "\n";
  std::cout << "relics:\n";
  for (const auto& name : sim::builtinRelicNames()) std::cout << name << "\n";
  return 0;
}

int describeScene(const std::string& name_or_file) {
  const sim::SceneDescription d = sim::loadScene(name_or_file);
  const auto& c = d.camera;
  const auto& n = d.noise;
  std::cout << "scene: " << d.name << "\n"
            << "source: " << d.source << "\n";
  if (const std::string what = sim::describeBuiltinScene(d.name); !what.empty() && d.source == "built-in")
    std::cout << "about: " << what << "\n";
  std::cout << "hall: " << d.hall << "\n"
            << "relic: " << d.relic << (d.fit_relic ? " (fitted on the pedestal)" : "") << "\n";
  if (d.relic_roughness >= 0) std::cout << "relic roughness: " << d.relic_roughness << "\n";
  if (d.relic_metallic >= 0) std::cout << "relic metallic: " << d.relic_metallic << "\n";
  std::cout << "visitors: " << d.visitors << "\n"
            << "seed: " << d.seed << "\n"
            << "cameras: 4 x " << c.width << "x" << c.height << ", " << c.hfov_deg << " x " << c.vfov_deg
            << " deg, range " << c.min_range << "-" << c.max_range << " m, " << c.fps << " fps, exposure "
            << c.exposure << "\n"
            << "depth noise: " << (n.enabled ? "on" : "off") << ", sigma(z) = " << n.sigma_0 << " + "
            << n.k_z2 << " z^2 m, grazing dropout beyond " << n.grazing_dropout_deg << " deg, edge dropout "
            << n.edge_dropout << ", flying pixels " << n.flying_pixel << ", random dropout "
            << n.random_dropout << ", colour sigma " << n.colour_sigma << "\n"
            << "panorama position (m): " << d.panorama_position.x << " " << d.panorama_position.y << " "
            << d.panorama_position.z << "\n";
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "scenes",
    [](CLI::App& sub) {
      auto scene = std::make_shared<std::string>();
      sub.add_option("scene", *scene, "A built-in scene name or a .yaml scene file to describe");
      return [scene] { return scene->empty() ? listScenes() : describeScene(*scene); };
    },
    "List the built-in simulated scenes and relics, or describe one"});

}  // namespace holo::app
