#include "reflection_setup.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/foreground_environment.hpp"
#include "holo/reflect/ibl_renderer.hpp"
#include "holo/reflect/path_tracer.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/reflect/view.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/relics.hpp"

namespace holo::app {
namespace {

constexpr int kPanoramaWidth = 1024, kPanoramaHeight = 512;

std::uint64_t fnv1a(std::uint64_t h, const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}
std::uint64_t fnv1a(std::uint64_t h, const std::string& s) {
  return fnv1a(h, s.data(), s.size());
}

bool isBuiltinRelic(const std::string& name) {
  const auto names = sim::builtinRelicNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

vec3 parseVec3(const std::string& text, const std::string& field) {
  std::stringstream in(text);
  vec3 v(0.0f);
  char comma = 0;
  if (!(in >> v.x >> comma >> v.y >> comma >> v.z) || !isFinite(v))
    throw InputError("command line", field, "three finite numbers X,Y,Z (metres)", text);
  return v;
}

// The visitors as the four depth cameras see them: every foreground pixel with a true depth,
// back-projected into the world with its linear radiance (what a perfect depth filter gives).
depthfilter::ForegroundCloud foregroundFromCameras(const sim::Museum& museum, int frame) {
  depthfilter::ForegroundCloud cloud;
  cloud.sequence = frame;
  cloud.time_s = museum.frameTime(frame);
  const float exposure = museum.description().camera.exposure;
  for (int c = 0; c < museum.cameraCount(); ++c) {
    const sim::SimulatedFrame f = museum.renderCamera(c, frame, true);
    const CameraModel& camera = museum.camera(c);
    for (int y = 0; y < f.true_depth.rows; ++y)
      for (int x = 0; x < f.true_depth.cols; ++x) {
        const float z = f.true_depth.at<float>(y, x);
        if (f.foreground.at<uchar>(y, x) == 0 || !(z > 0.0f)) continue;
        const cv::Vec3b bgr = f.frame.color.at<cv::Vec3b>(y, x);
        depthfilter::ForegroundPoint p;
        p.position = camera.unproject(vec2(x, y), z);
        p.radiance = vec3(srgbToLinear(bgr[2] / 255.0f), srgbToLinear(bgr[1] / 255.0f),
                          srgbToLinear(bgr[0] / 255.0f)) /
                     std::max(exposure, 1e-6f);
        p.camera = std::uint16_t(c);
        p.x = std::uint16_t(x);
        p.y = std::uint16_t(y);
        cloud.points.push_back(p);
      }
  }
  return cloud;
}

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void SceneOptions::addTo(CLI::App& app) {
  app.add_option("--scene", scene, "Built-in scene name or YAML file; 'empty' = relic alone")
      ->capture_default_str();
  app.add_option("--relic", relic, "Built-in relic name or glTF file (default: the scene's)");
  app.add_option("--panorama", panorama,
                 "HDR/EXR panorama (default: the museum hall rendered from the pyramid)");
  app.add_flag("--fit", fit, "Scale and centre a relic file on the pedestal");
  app.add_option("--frame", frame, "Museum frame (visitor poses)")->capture_default_str();
}

void ViewOptions::addTo(CLI::App& app) {
  app.add_option("--width", width, "Image width, pixels")->capture_default_str()->check(CLI::Range(1, 8192));
  app.add_option("--height", height, "Image height, pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, 8192));
  app.add_option("--face", face, "Pyramid face 0..3 (+Z, +X, -Z, -X)")
      ->capture_default_str()
      ->check(CLI::Range(0, 3));
  app.add_option("--eye", eye, "Explicit eye X,Y,Z (metres, world frame)");
  app.add_option("--look-at", look_at, "Explicit target X,Y,Z (default: the relic's centre)");
  app.add_option("--fov-deg", fov_deg, "Vertical field of view, degrees (default: frame the relic)");
}

ReflectionScene loadReflectionScene(const SceneOptions& o) {
  ReflectionScene s;
  s.scene_name = o.scene;
  s.floor_y = -sim::kBaseHeight;
  std::optional<sim::Museum> museum;
  if (o.scene == "empty") {
    s.relic_name = o.relic.empty() ? "vase" : o.relic;
    if (isBuiltinRelic(s.relic_name)) {
      s.relic = sim::makeRelic(s.relic_name);
      sim::fitOnPedestal(s.relic);
    } else {
      s.relic = loadGltf(s.relic_name);
      if (o.fit) sim::fitOnPedestal(s.relic);
    }
    if (o.panorama.empty()) {
      museum.emplace(sim::loadScene("empty"));  // the empty hall, for its panorama only
    }
  } else {
    sim::SceneDescription d = sim::loadScene(o.scene);
    if (!o.relic.empty()) {
      d.relic = o.relic;
      d.fit_relic = isBuiltinRelic(o.relic) || o.fit;
    }
    museum.emplace(d);
    s.relic_name = d.relic;
    s.relic = museum->relic();
    s.static_emitters.push_back(museum->hall());
    s.visitors = museum->visitors(o.frame);
    s.foreground = foregroundFromCameras(*museum, o.frame);
  }
  s.panorama = o.panorama.empty() ? museum->renderPanorama(kPanoramaWidth, kPanoramaHeight)
                                  : loadHdr(o.panorama).pixels;
  std::uint64_t h = 1469598103934665603ull;
  h = fnv1a(h, o.scene + "|" + s.relic_name + "|" + std::to_string(o.fit) + "|" + std::to_string(o.frame));
  const cv::Mat pano = s.panorama.isContinuous() ? s.panorama : s.panorama.clone();
  h = fnv1a(h, pano.data, pano.total() * pano.elemSize());
  s.hash = h;
  return s;
}

CameraModel viewCamera(const ViewOptions& v, const ReflectionScene& scene) {
  const Bounds3 bounds = scene.relic.bounds();
  const vec3 target =
      v.look_at.empty() ? (bounds.empty() ? vec3(0.0f) : bounds.center()) : parseVec3(v.look_at, "--look-at");
  const vec3 eye =
      v.eye.empty() ? reflect::defaultFaceEye(v.face, bounds, scene.floor_y) : parseVec3(v.eye, "--eye");
  if (glm::length(eye - target) < 1e-4f)
    throw InputError("command line", "--eye", "an eye apart from the target", v.eye);
  const float fov = v.fov_deg > 0.0f ? v.fov_deg : reflect::framingFovDeg(eye, bounds);
  return reflect::lookAtCamera(eye, target, fov, v.width, v.height);
}

MethodResult renderMethod(const std::string& method, const ReflectionScene& scene, const CameraModel& camera,
                          const MethodSettings& settings, bool quiet) {
  MethodResult r;
  const auto t0 = std::chrono::steady_clock::now();
  if (method == "gt") {
    std::vector<Model> emitters = scene.static_emitters;
    if (settings.with_visitors && !scene.visitors.meshes.empty()) emitters.push_back(scene.visitors);
    const reflect::RenderScene rs(scene.relic, emitters);
    const reflect::Environment env(scene.panorama);
    reflect::PathTracerOptions options;
    options.seed = settings.seed;
    const reflect::PathTracer tracer(rs, env, options);
    r.image = reflect::renderPathTraced(tracer, camera, std::max(1, settings.spp), nullptr, quiet);
  } else if (method == "ibl" || method == "ibl-baseline") {
    const reflect::RenderScene rs(scene.relic, {});
    const bool merge = method == "ibl-baseline" && settings.with_visitors;
    const Bounds3 b = scene.relic.bounds();
    const cv::Mat pano = merge ? reflect::mergeForeground(scene.panorama, scene.foreground,
                                                          b.empty() ? vec3(0.0f) : b.center())
                               : scene.panorama;
    const reflect::Environment env(pano);
    reflect::PrefilterOptions po;
    po.levels = settings.ibl_levels;
    const reflect::PrefilteredIbl ibl(env, po);
    r.build_ms = msSince(t0);
    r.image = reflect::renderIbl(rs, ibl, camera);
  } else {
    std::string names;
    for (const auto& m : reflectionMethods()) names += (names.empty() ? "" : ", ") + m;
    throw InputError("command line", "--method", "one of " + names, method);
  }
  r.ms = msSince(t0);
  return r;
}

void writeImagePair(const std::string& exr_path, const cv::Mat& hdr, float exposure) {
  saveHdr(exr_path, hdr);
  const std::filesystem::path png = std::filesystem::path(exr_path).replace_extension(".png");
  const cv::Mat ldr = reflect::toneMap(hdr, exposure > 0.0f ? exposure : reflect::autoExposure(hdr));
  writeAtomically(png, [&](const std::filesystem::path& tmp) {
    if (!cv::imwrite(tmp.string() + ".png", ldr)) throw Error("could not write " + png.string());
    std::filesystem::rename(tmp.string() + ".png", tmp);
  });
}

}  // namespace holo::app
