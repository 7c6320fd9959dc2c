#include "holo/eval/reflection_scene.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/core/image.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/render_scene.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"
#include "holo/sim/halls.hpp"
#include "holo/sim/museum.hpp"
#include "holo/simulated/museum_installation.hpp"

namespace holo::eval {
namespace {

constexpr int kPanoramaWidth = 1024, kPanoramaHeight = 512;

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
    image.colour_bgr = srgb8ToLinear(f.frame.colour) / exposure;
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
      throw InputError("command line", "--hall", "one of room, gallery, atrium, window, none", o.hall);
    d.hall = o.hall;
  }
  if (o.close_visitors >= 0) d.close_visitors = o.close_visitors;
  if (!o.visitor_model.empty())
    d.visitor_model = sim::visitorModelFromName(o.visitor_model, "command line", "--visitor-model");
  if (o.camera_vfov_deg > 0.0f) d.camera.vfov_deg = o.camera_vfov_deg;
  if (o.camera_tilt_deg != 0.0f) d.camera.tilt_deg = o.camera_tilt_deg;
  return d;
}

}  // namespace

ReflectionScene loadReflectionScene(const SceneOptions& o) {
  ReflectionScene s;
  s.scene_name = o.scene;
  s.floor_y = -sim::kBaseHeight;
  std::optional<sim::Museum> museum;
  if (o.scene == "empty") {
    s.relic_name = o.relic.empty() ? "vase" : o.relic;
    if (isBuiltinRelic(s.relic_name)) {
      s.relic = relics::makeRelic(s.relic_name);
      relics::fitOnPedestal(s.relic);
    } else {
      s.relic = loadGltf(s.relic_name);
      if (o.fit) relics::fitOnPedestal(s.relic);
    }
    if (o.panorama.empty()) {
      museum.emplace(sim::loadScene("empty"));  // the empty hall, for its panorama only
    }
  } else {
    const sim::SceneDescription d = sceneDescription(o);
    museum.emplace(d);
    s.relic_name = d.relic;
    s.relic = museum->relic();
    s.plinth = d.plinth;
    s.static_emitters.push_back(museum->hall());
    s.visitors = museum->visitors(o.frame);
    foregroundFromCameras(*museum, o.frame, s);
  }
  s.panorama = o.panorama.empty() ? museum->renderPanorama(kPanoramaWidth, kPanoramaHeight)
                                  : loadHdr(o.panorama).pixels;
  // As the live simulated installation places it; the relic alone ("empty") has no hall in its
  // truth, so its panorama stays at infinity.
  if (o.panorama.empty() && !s.static_emitters.empty() && !o.panorama_at_infinity)
    s.panorama_proxy = simulated::museumPanoramaProxy(*museum);
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
      int relic_pixels = 0, reflected = 0, seen_through = 0, either = 0;
      const reflect::HitPointBuffer& h = hits[std::size_t(f)];
      for (std::size_t i = 0; i < h.hits.size(); ++i) {
        if (!h.valid[i]) continue;
        ++relic_pixels;
        const reflect::HitPoint& hp = h.hits[i];
        const bool mirror =
            visitors.all().intersect(Ray{hp.position + hp.normal * 1e-3f, hp.reflected}).hit();
        // The straight continuation stands in for the refracted path: it only picks the view, and
        // a thick wall's refraction offsets the ray more than it turns it.
        const bool through =
            hp.gltf != nullptr && hp.gltf->transmissive() &&
            visitors.all().intersect(Ray{hp.position - hp.normal * 1e-3f, -hp.to_viewer}).hit();
        reflected += mirror;
        seen_through += through;
        either += mirror || through;
      }
      const auto share = [&](int n) { return relic_pixels > 0 ? float(n) / float(relic_pixels) : 0.0f; };
      if (share(either) > best_score)
        best_score = share(either), best = {frame, f, share(reflected), share(seen_through)};
    }
  }
  return best;
}

VisitorScene visitorScene(const std::string& hall, const std::string& relic, int close_visitors,
                          float camera_tilt_deg, float camera_vfov_deg, int size,
                          const std::string& visitor_model, bool panorama_at_infinity) {
  SceneOptions so;
  so.scene = hall;  // the built-in scene of that hall: its visitors
  so.hall = hall;
  so.relic = relic;
  so.close_visitors = close_visitors;
  so.visitor_model = visitor_model;
  so.panorama_at_infinity = panorama_at_infinity;
  so.camera_tilt_deg = camera_tilt_deg;
  so.camera_vfov_deg = camera_vfov_deg;
  VisitorScene s;
  s.pick = visitorView(so);
  so.frame = s.pick.frame;
  s.scene = loadReflectionScene(so);
  ViewOptions vo;
  vo.width = vo.height = size;
  vo.face = s.pick.face;
  s.camera = viewCamera(vo, s.scene);
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

}  // namespace holo::eval
