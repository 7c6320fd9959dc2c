// `holopyramid render`: one face view (or an explicit camera) of the relic with one reflection
// method, written as linear HDR EXR plus a tone-mapped PNG beside it.
#include <iostream>
#include <memory>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/eval/scoring.hpp"

namespace holo::app {

using namespace holo::eval;
namespace {

struct RenderOptions {
  SceneOptions scene;
  ViewOptions view;
  std::string method = "gt";
  MethodSettings settings;
  std::string out;
  bool no_visitors = false;
};

int render(const RenderOptions& o) {
  if (o.out.empty()) throw InputError("command line", "--out", "an output file FILE.exr");
  const ReflectionScene scene = loadReflectionScene(o.scene);
  const CameraModel camera = viewCamera(o.view, scene);
  MethodSettings settings = o.settings;
  settings.with_visitors = !o.no_visitors;
  const MethodResult result = renderMethod(o.method, scene, camera, settings, false);
  writeImagePair(o.out, result.image);
  std::cout << "method: " << o.method << "\n"
            << "scene: " << scene.scene_name << "\n"
            << "relic: " << scene.relic_name << "\n"
            << "size: " << camera.width() << "x" << camera.height() << "\n"
            << "ms: " << result.ms << "\n"
            << "out: " << o.out << "\n";
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "render",
    [](CLI::App& sub) {
      auto o = std::make_shared<RenderOptions>();
      addSceneOptions(sub, o->scene);
      addViewOptions(sub, o->view);
      sub.add_option("--method", o->method, "gt | ibl | ibl-baseline | ours | ssrt | mcpt")
          ->capture_default_str();
      sub.add_option("--spp", o->settings.spp, "gt: samples per pixel")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 20));
      sub.add_option("--seed", o->settings.seed, "gt: sampling seed")->capture_default_str();
      sub.add_option("--max-bounces", o->settings.max_bounces,
                     "gt: scattering events on the relic per path (what the last one reaches counts)")
          ->capture_default_str()
          ->check(CLI::Range(1, 1024));
      sub.add_option("--max-dielectric-bounces", o->settings.max_dielectric_bounces,
                     "gt: reflections and refractions on glass per path, counted apart from --max-bounces")
          ->capture_default_str()
          ->check(CLI::Range(1, 4096));
      sub.add_option("--ibl-levels", o->settings.ibl_levels, "ibl: roughness levels")
          ->capture_default_str()
          ->check(CLI::Range(2, 64));
      sub.add_option("--ibl-texel-density", o->settings.ibl_texel_density,
                     "ibl: a level of roughness r is max(48, density / r) texels wide")
          ->capture_default_str()
          ->check(CLI::Range(1, 1024));
      sub.add_option("--refraction-depth", o->settings.tracer.refraction_depth,
                     "ours: interface events a transmitted path follows (0: measured on the relic)")
          ->capture_default_str()
          ->check(CLI::Range(0, 32));
      sub.add_flag("--no-visitors", o->no_visitors, "Leave the visitors out");
      sub.add_option("--out", o->out, "Output FILE.exr (a tone-mapped FILE.png is written beside it)")
          ->required();
      return [o] { return render(*o); };
    },
    "Render the relic's reflections with one method (EXR + PNG)"});

}  // namespace holo::app
