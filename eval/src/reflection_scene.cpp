#include "holo/eval/reflection_scene.hpp"

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
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/ibl_renderer.hpp"
#include "holo/reflect/path_tracer.hpp"
#include "holo/reflect/ssrt.hpp"
#include "holo/reflect/tone_map.hpp"
#include "holo/reflect/view.hpp"
#include "holo/reflect/voxel_emitters.hpp"
#include "holo/sim/halls.hpp"
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
// back-projected into the world with its linear radiance (what a perfect depth filter gives),
// and each camera's linear colour and true foreground mask (what ours' pyramids are built from).
void foregroundFromCameras(const sim::Museum& museum, int frame, ReflectionScene& s) {
  depthfilter::ForegroundCloud& cloud = s.foreground;
  cloud.sequence = frame;
  cloud.time_s = museum.frameTime(frame);
  const float exposure = std::max(museum.description().camera.exposure, 1e-6f);
  for (int c = 0; c < museum.cameraCount(); ++c) {
    const sim::SimulatedFrame f = museum.renderCamera(c, frame, true);
    reflect::ForegroundCameraImage image;
    image.camera = museum.camera(c);
    image.colour_bgr = srgb8ToLinear(f.frame.color) / exposure;
    image.mask = f.foreground;
    for (int y = 0; y < f.true_depth.rows; ++y)
      for (int x = 0; x < f.true_depth.cols; ++x) {
        const float z = f.true_depth.at<float>(y, x);
        if (f.foreground.at<uchar>(y, x) == 0 || !(z > 0.0f)) continue;
        depthfilter::ForegroundPoint p;
        p.position = image.camera.unproject(vec2(x, y), z);
        p.radiance = rgbAt(image.colour_bgr, x, y);
        p.camera = std::uint16_t(c);
        p.x = std::uint16_t(x);
        p.y = std::uint16_t(y);
        cloud.points.push_back(p);
      }
    s.foreground_cameras.push_back(std::move(image));
  }
}

sim::SceneDescription sceneDescription(const SceneOptions& o) {
  sim::SceneDescription d = sim::loadScene(o.scene);
  if (!o.relic.empty()) {
    d.relic = o.relic;
    d.fit_relic = isBuiltinRelic(o.relic) || o.fit;
  }
  if (!o.hall.empty()) {
    const auto halls = sim::hallNames();
    if (std::find(halls.begin(), halls.end(), o.hall) == halls.end())
      throw InputError("command line", "--hall", "one of room, gallery, atrium, none", o.hall);
    d.hall = o.hall;
  }
  if (o.close_visitors >= 0) d.close_visitors = o.close_visitors;
  if (o.camera_vfov_deg > 0.0f) d.camera.vfov_deg = o.camera_vfov_deg;
  if (o.camera_tilt_deg != 0.0f) d.camera.tilt_deg = o.camera_tilt_deg;
  return d;
}

std::string hex(std::uint64_t v) {
  std::ostringstream s;
  s << std::hex << v;
  return s.str();
}

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void SceneOptions::addTo(CLI::App& app) {
  app.add_option("--scene", scene, "Built-in scene name or YAML file; 'empty' = relic alone")
      ->capture_default_str();
  app.add_option("--relic", relic, "Built-in relic name or glTF file (default: the scene's)");
  app.add_option("--hall", hall, "Built-in hall (room, gallery, atrium) instead of the scene's");
  app.add_option("--panorama", panorama,
                 "HDR/EXR panorama (default: the museum hall rendered from the pyramid)");
  app.add_flag("--fit", fit, "Scale and centre a relic file on the pedestal");
  app.add_option("--frame", frame, "Museum frame (visitor poses)")->capture_default_str();
  app.add_option("--close-visitors", close_visitors,
                 "Visitors standing close to the pyramid, reaching out to it (default: the scene's)")
      ->check(CLI::Range(0, 4));
  app.add_option("--camera-vfov-deg", camera_vfov_deg,
                 "Depth cameras' vertical field of view, degrees (default: the scene's)")
      ->check(CLI::Range(10.0f, 170.0f));
  app.add_option("--camera-tilt-deg", camera_tilt_deg,
                 "Depth cameras' upwards tilt, degrees (default: the scene's)")
      ->check(CLI::Range(-60.0f, 60.0f));
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
    const sim::SceneDescription d = sceneDescription(o);
    museum.emplace(d);
    s.relic_name = d.relic;
    s.relic = museum->relic();
    s.static_emitters.push_back(museum->hall());
    s.visitors = museum->visitors(o.frame);
    foregroundFromCameras(*museum, o.frame, s);
  }
  s.panorama = o.panorama.empty() ? museum->renderPanorama(kPanoramaWidth, kPanoramaHeight)
                                  : loadHdr(o.panorama).pixels;
  std::uint64_t h = 1469598103934665603ull;
  h = fnv1a(h, o.scene + "|" + s.relic_name + "|" + std::to_string(o.fit) + "|" + std::to_string(o.frame) +
                   (o.hall.empty() ? "" : "|" + o.hall) +
                   (o.close_visitors < 0 ? "" : "|close" + std::to_string(o.close_visitors)) +
                   (o.camera_vfov_deg > 0.0f ? "|vfov" + std::to_string(o.camera_vfov_deg) : "") +
                   (o.camera_tilt_deg != 0.0f ? "|tilt" + std::to_string(o.camera_tilt_deg) : ""));
  const cv::Mat pano = s.panorama.isContinuous() ? s.panorama : s.panorama.clone();
  h = fnv1a(h, pano.data, pano.total() * pano.elemSize());
  s.hash = h;
  return s;
}

VisitorView visitorView(const SceneOptions& o) {
  VisitorView best;
  if (o.scene == "empty") return best;
  const sim::Museum museum(sceneDescription(o));
  const reflect::RenderScene relic(museum.relic(), {});
  const Bounds3 bounds = museum.relic().bounds();
  constexpr int kFrames = 300, kStride = 10, kSize = 48;  // ten seconds at 30 fps
  std::vector<CameraModel> faces;
  for (int f = 0; f < 4; ++f) {
    const vec3 eye = reflect::defaultFaceEye(f, bounds, -sim::kBaseHeight);
    faces.push_back(
        reflect::lookAtCamera(eye, bounds.center(), reflect::framingFovDeg(eye, bounds), kSize, kSize));
  }
  std::vector<reflect::HitPointBuffer> hits;
  for (const CameraModel& c : faces) {
    hits.emplace_back();
    reflect::traceHitPoints(relic, c, reflect::AntiAliasing::None, hits.back());
  }
  float best_score = -1.0f;
  for (int frame = 0; frame < kFrames; frame += kStride) {
    const reflect::RenderScene visitors(Model{}, {museum.visitors(frame)});
    for (int f = 0; f < 4; ++f) {
      int relic_pixels = 0, met = 0;
      const reflect::HitPointBuffer& h = hits[std::size_t(f)];
      for (std::size_t i = 0; i < h.hits.size(); ++i) {
        if (!h.valid[i]) continue;
        ++relic_pixels;
        const reflect::HitPoint& hp = h.hits[i];
        met += visitors.all().intersect(Ray{hp.position + hp.normal * 1e-3f, hp.reflected}).hit();
      }
      const float fraction = relic_pixels > 0 ? float(met) / float(relic_pixels) : 0.0f;
      if (fraction > best_score) best_score = fraction, best = {frame, f, fraction};
    }
  }
  return best;
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

std::shared_ptr<const reflect::PrefilteredIbl> staticIbl(const ReflectionScene& scene,
                                                         const MethodSettings& settings) {
  const reflect::Environment env(scene.panorama);
  reflect::PrefilterOptions po;
  po.levels = settings.ibl_levels;
  po.texel_density = settings.ibl_texel_density;
  return std::make_shared<const reflect::PrefilteredIbl>(env, po);
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
  } else if (method == "ibl" && settings.static_ibl) {
    // The static map is built once per scene: the per-view cost is the shading alone (the
    // relic's Embree scene is built once too, as for ours).
    const reflect::RenderScene rs(scene.relic, {});
    const auto t1 = std::chrono::steady_clock::now();
    r.image = reflect::renderIbl(rs, *settings.static_ibl, camera);
    r.ms = msSince(t1);
    return r;
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
  } else if (method == "ours" || method == "ssrt") {
    const reflect::RenderScene rs(scene.relic, {});
    std::shared_ptr<const reflect::PrefilteredIbl> ibl = settings.static_ibl;
    if (!ibl) {
      ibl = staticIbl(scene, settings);
      r.build_ms = msSince(t0);
    }
    static const depthfilter::ForegroundCloud kNobody;
    const depthfilter::ForegroundCloud& cloud = settings.with_visitors ? scene.foreground : kNobody;
    if (method == "ours") {
      reflect::FrameRenderer renderer(rs, *ibl, settings.tracer);
      // Timed as the live loop runs it, where the eyes move every frame: buffers already
      // allocated and touched by a frame before (the grid, the pyramids, the view's hit points),
      // the view's static passes traced again (the eye 1 mm away: no reuse).
      CameraModel moved_eye = camera;
      mat4 pose = camera.T_world_camera();
      pose[3] += vec4(0.001f, 0.0f, 0.0f, 0.0f);
      moved_eye.setPose(pose);
      renderer.render(cloud, scene.foreground_cameras, {moved_eye});
      const auto t1 = std::chrono::steady_clock::now();
      reflect::FrameResult fr = renderer.render(cloud, scene.foreground_cameras, {camera});
      r.ms = msSince(t1);
      for (const reflect::PassTiming& p : fr.frame_timings) {
        r.passes.emplace_back(reflect::passName(p.pass), p.ms);
        r.frame_ms += p.ms;
      }
      for (const reflect::PassTiming& p : fr.views.at(0).timings) {
        r.passes.emplace_back(reflect::passName(p.pass), p.ms);
        r.view_ms += p.ms;
      }
      r.image = std::move(fr.views.at(0).hdr);
    } else {
      reflect::SsrtSettings ss;
      ss.rays = std::max(1, settings.spp);
      ss.seed = settings.seed;
      const auto t1 = std::chrono::steady_clock::now();
      r.image = reflect::renderSsrt(rs, *ibl, cloud, camera, ss);
      r.ms = msSince(t1);
    }
    return r;
  } else if (method == "mcpt") {
    depthfilter::VoxelGrid grid;
    if (settings.with_visitors) grid.build(scene.foreground);
    std::vector<Model> emitters;
    if (!grid.empty()) emitters.push_back(reflect::voxelEmitters(grid));
    const reflect::RenderScene rs(scene.relic, emitters);
    const reflect::Environment env(scene.panorama);
    reflect::PathTracerOptions options;
    options.seed = settings.seed;
    const reflect::PathTracer tracer(rs, env, options);
    r.build_ms = msSince(t0);
    r.image = reflect::renderPathTraced(tracer, camera, std::max(1, settings.spp), nullptr, quiet);
  } else {
    std::string names;
    for (const auto& m : reflectionMethods()) names += (names.empty() ? "" : ", ") + m;
    throw InputError("command line", "--method", "one of " + names, method);
  }
  r.ms = msSince(t0);
  return r;
}

cv::Mat cachedGroundTruth(const ReflectionScene& scene, const CameraModel& camera, int spp,
                          bool with_visitors, const std::filesystem::path& cache) {
  // The view enters the key through its pose and intrinsics, bit for bit.
  const mat4& pose = camera.T_world_camera();
  const Intrinsics& K = camera.intrinsics();
  std::string view(reinterpret_cast<const char*>(&pose[0][0]), sizeof(mat4));
  view.append(reinterpret_cast<const char*>(&K.fx), 4 * sizeof(float));
  const std::string key = hex(scene.hash) + "-" + std::to_string(camera.width()) + "x" +
                          std::to_string(camera.height()) + "-" + hex(std::hash<std::string>{}(view)) +
                          "-spp" + std::to_string(spp) + (with_visitors ? "" : "-novisitors");
  const std::filesystem::path file = cache / ("gt-" + key + ".exr");
  if (std::filesystem::exists(file)) {
    const cv::Mat cached = loadHdr(file).pixels;
    if (cached.cols == camera.width() && cached.rows == camera.height()) return cached;
  }
  MethodSettings s;
  s.spp = spp;
  s.with_visitors = with_visitors;
  const cv::Mat image = renderMethod("gt", scene, camera, s, false).image;
  std::filesystem::create_directories(cache);
  saveHdr(file, image);
  return image;
}

cv::Mat displayedImage(const cv::Mat& hdr, float exposure) {
  cv::Mat out;
  reflect::toneMap(hdr, exposure).convertTo(out, CV_32FC3, 1.0 / 255.0);
  return out;
}

void writePng(const std::filesystem::path& path, const cv::Mat& bgr8) {
  writeAtomically(path, [&](const std::filesystem::path& tmp) {
    if (!cv::imwrite(tmp.string() + ".png", bgr8)) throw Error("could not write " + path.string());
    std::filesystem::rename(tmp.string() + ".png", tmp);
  });
}

void writeImagePair(const std::string& exr_path, const cv::Mat& hdr, float exposure) {
  saveHdr(exr_path, hdr);
  const std::filesystem::path png = std::filesystem::path(exr_path).replace_extension(".png");
  writePng(png, reflect::toneMap(hdr, exposure > 0.0f ? exposure : reflect::autoExposure(hdr)));
}

}  // namespace holo::app
