// `holopyramid render`: one face view (or an explicit camera) of the relic with one reflection
// method, written as linear HDR EXR plus a tone-mapped PNG beside it; or, with --ar-camera N, the
// AR check view of an installation's camera N (pipeline/ar_check_view.hpp) as a PNG (and the
// linear EXR when FILE.exr is asked for).
#include <filesystem>
#include <iostream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <string_view>
#include <vector>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/eval/scoring.hpp"
#include "holo/pipeline/ar_check_view.hpp"
#include "holo/simulated/museum_installation.hpp"

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
  bool no_visitor_light = false;
  int ar_camera = -1;
  std::string ar_config;
  int ar_spp = 16;
  bool scene_given = false;
};

int renderAr(const RenderOptions& o) {
  pipeline::FrameLoopOptions loop;
  loop.scene = o.scene_given ? o.scene.scene : "museum";
  loop.relic = o.scene.relic;
  loop.config = o.ar_config;
  pipeline::Installation installation = simulated::installationFor(loop);
  ar::ArViewSettings settings;
  settings.composite.spp = o.ar_spp;
  settings.composite.seed = o.settings.seed;
  const ar::ArView view = pipeline::arCheckView(installation, o.ar_camera, settings);
  // FILE.exr: the linear radiance, and FILE.png beside it; otherwise the PNG alone.
  std::filesystem::path png_path = o.out;
  if (png_path.extension() == ".exr") {
    saveHdr(png_path, view.radiance);
    png_path.replace_extension(".png");
  }
  std::vector<uchar> png;
  if (!cv::imencode(".png", view.image, png))
    throw InputError(o.out, "--out", "a PNG the image can be encoded as");
  writeFileAtomically(png_path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  std::cout << "ar camera: " << o.ar_camera << "\n"
            << "installation: " << installation.name << "\n"
            << "relic: " << (installation.relic_name.empty() ? "the scene's" : installation.relic_name)
            << "\n"
            << "size: " << view.image.cols << "x" << view.image.rows << "\n"
            << "relic pixels: " << view.relic_pixels
            << (view.relic_pixels == 0 ? " (the relic is outside this camera's view)" : "") << "\n"
            << "real surface vertices: " << view.real_vertices << "\n"
            << "rays: " << view.rays << "\n"
            << "caustic photons: " << view.caustic_photons
            << (view.caustic_photons == 0 ? " (no transmissive relic standing on the base)" : "") << "\n"
            << "out: " << o.out << "\n";
  return 0;
}

int render(const RenderOptions& o) {
  if (o.out.empty()) throw InputError("command line", "--out", "an output file FILE.exr");
  if (o.ar_camera != -1) return renderAr(o);
  const ReflectionScene scene = loadReflectionScene(o.scene);
  const CameraModel camera = viewCamera(o.view, scene);
  MethodSettings settings = o.settings;
  settings.with_visitors = !o.no_visitors;
  settings.tracer.evaluation.visitor_light = !o.no_visitor_light;
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
      sub.add_flag("--no-visitor-light", o->no_visitor_light,
                   "ours: the visitors neither shadow nor light the relic's diffuse and widest lobes");
      sub.add_option("--ar-camera", o->ar_camera,
                     "The AR check view of camera N (of --ar-config, else of the simulated museum --scene, "
                     "museum by default: cameras 0-3 the rig's, 4 its check camera): the relic composited "
                     "over its image with its shadow and light, "
                     "by delta path tracing (--out FILE.png, or FILE.exr with FILE.png beside it)");
      sub.add_option("--ar-config", o->ar_config,
                     "--ar-camera: a configuration file with capture: and exhibit:");
      sub.add_option("--ar-spp", o->ar_spp, "--ar-camera: samples per pixel")
          ->capture_default_str()
          ->check(CLI::Range(1, 1 << 16));
      sub.add_option("--out", o->out, "Output FILE.exr (a tone-mapped FILE.png is written beside it)")
          ->required();
      CLI::Option* scene_option = sub.get_option("--scene");
      return [o, scene_option] {
        o->scene_given = scene_option->count() > 0;
        return render(*o);
      };
    },
    "Render the relic's reflections with one method (EXR + PNG)"});

}  // namespace holo::app
