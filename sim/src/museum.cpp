#include "holo/sim/museum.hpp"

#include <tbb/parallel_for.h>
#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>
#include <set>

#include "holo/core/config.hpp"
#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/image.hpp"
#include "holo/core/ray_scene.hpp"
#include "holo/relics/relics.hpp"
#include "holo/sim/halls.hpp"
#include "holo/sim/sensor_noise.hpp"
#include "holo/sim/visitors.hpp"

namespace holo::sim {

namespace fs = std::filesystem;

namespace {

constexpr float kCameraDrop = 0.12f;               // camera centres sit this far below the base top
constexpr std::uint64_t kBackgroundFrame = ~0ull;  // noise stream of the background frames

struct Builtin {
  const char* name;
  const char* hall;
  const char* relic;
  int visitors;
  const char* what;
  int close_visitors = 0;
};
// The default demo is "museum"; the halls x relics of the evaluation are the other names.
constexpr Builtin kBuiltins[] = {
    {"museum", "gallery", "vase", 3, "gallery, bronze vase, three visitors (the default demo)"},
    {"room", "room", "kettle", 2, "small living room, silver kettle, two visitors"},
    {"gallery", "gallery", "tripod", 3, "long gallery, tripod vessel, three visitors"},
    {"atrium", "atrium", "vase", 4, "tall atrium with a skylight, vase, four visitors"},
    {"mirror", "gallery", "sphere", 2, "gallery, mirror sphere, two visitors"},
    {"empty", "gallery", "vase", 0, "gallery, vase, nobody there"},
    {"window", "window", "bowl", 0,
     "room lit by a bright window, clay bowl, one visitor standing between them", 1},
};

bool isRelicName(const std::string& relic) {
  const auto names = relics::relicNames();
  return std::find(names.begin(), names.end(), relic) != names.end();
}

void readCamera(const ConfigNode& node, CameraSettings& c) {
  static const std::set<std::string> known = {"width",     "height",    "hfov_deg", "vfov_deg", "tilt_deg",
                                              "min_range", "max_range", "fps",      "exposure"};
  for (const auto& key : node.keys())
    if (!known.count(key))
      node[key].fail(
          "one of width, height, hfov_deg, vfov_deg, tilt_deg, min_range, max_range, fps, exposure", key);
  if (node.has("width")) {
    c.width = node["width"].as<int>();
    if (c.width < 8 || c.width > 8192)
      node["width"].fail("an image width in [8, 8192]", std::to_string(c.width));
  }
  if (node.has("height")) {
    c.height = node["height"].as<int>();
    if (c.height < 8 || c.height > 8192)
      node["height"].fail("an image height in [8, 8192]", std::to_string(c.height));
  }
  c.hfov_deg = node.getInRange("hfov_deg", c.hfov_deg, 10.0f, 170.0f);
  c.vfov_deg = node.getInRange("vfov_deg", c.vfov_deg, 10.0f, 170.0f);
  c.tilt_deg = node.getInRange("tilt_deg", c.tilt_deg, -60.0f, 60.0f);
  c.min_range = node.getInRange("min_range", c.min_range, 0.0f, 100.0f);
  c.max_range = node.getInRange("max_range", c.max_range, 0.01f, 1000.0f);
  if (c.max_range <= c.min_range)
    node["max_range"].fail("max_range > min_range", std::to_string(c.max_range));
  c.fps = node.getInRange("fps", c.fps, 0.1f, 1000.0f);
  c.exposure = node.getInRange("exposure", c.exposure, 0.0f, 1e6f);
}

void readNoise(const ConfigNode& node, SensorNoise& n) {
  static const std::set<std::string> known = {"sigma_0",
                                              "k_z1",
                                              "k_z2",
                                              "grazing_dropout_deg",
                                              "edge_dropout",
                                              "flying_pixel",
                                              "random_dropout",
                                              "color_sigma",
                                              "enabled",
                                              "baseline",
                                              "native_focal_px",
                                              "disparity_step_px",
                                              "grazing_start_deg",
                                              "dark_luminance",
                                              "dark_dropout",
                                              "metal_dropout",
                                              "highlight_deg",
                                              "highlight_dropout",
                                              "range_fade_start",
                                              "range_fade_end",
                                              "edge_band_px",
                                              "low_texture_contrast",
                                              "low_texture_dropout",
                                              "edge_fattening_px",
                                              "hole_patch_px",
                                              "hole_flicker"};
  for (const auto& key : node.keys())
    if (!known.count(key))
      node[key].fail(
          "one of sigma_0, k_z1, k_z2, grazing_dropout_deg, edge_dropout, flying_pixel, random_dropout, "
          "color_sigma, enabled, baseline, native_focal_px, disparity_step_px, grazing_start_deg, "
          "dark_luminance, dark_dropout, metal_dropout, highlight_deg, highlight_dropout, range_fade_start, "
          "range_fade_end, edge_band_px, "
          "low_texture_contrast, low_texture_dropout, edge_fattening_px, hole_patch_px, hole_flicker",
          key);
  n.sigma_0 = node.getInRange("sigma_0", n.sigma_0, 0.0f, 1.0f);
  n.k_z1 = node.getInRange("k_z1", n.k_z1, 0.0f, 1.0f);
  n.k_z2 = node.getInRange("k_z2", n.k_z2, 0.0f, 1.0f);
  n.grazing_dropout_deg = node.getInRange("grazing_dropout_deg", n.grazing_dropout_deg, 0.0f, 90.0f);
  n.edge_dropout = node.getInRange("edge_dropout", n.edge_dropout, 0.0f, 1.0f);
  n.flying_pixel = node.getInRange("flying_pixel", n.flying_pixel, 0.0f, 1.0f);
  n.random_dropout = node.getInRange("random_dropout", n.random_dropout, 0.0f, 1.0f);
  n.colour_sigma = node.getInRange("color_sigma", n.colour_sigma, 0.0f, 255.0f);
  n.enabled = node.get<bool>("enabled", n.enabled);
  n.baseline = node.getInRange("baseline", n.baseline, 0.0f, 1.0f);
  n.native_focal_px = node.getInRange("native_focal_px", n.native_focal_px, 1.0f, 1e5f);
  n.disparity_step_px = node.getInRange("disparity_step_px", n.disparity_step_px, 0.0f, 10.0f);
  n.grazing_start_deg = node.getInRange("grazing_start_deg", n.grazing_start_deg, 0.0f, 90.0f);
  if (n.grazing_start_deg > n.grazing_dropout_deg)
    node["grazing_start_deg"].fail("grazing_start_deg <= grazing_dropout_deg",
                                   std::to_string(n.grazing_start_deg));
  n.dark_luminance = node.getInRange("dark_luminance", n.dark_luminance, 0.0f, 1e6f);
  n.dark_dropout = node.getInRange("dark_dropout", n.dark_dropout, 0.0f, 1.0f);
  n.metal_dropout = node.getInRange("metal_dropout", n.metal_dropout, 0.0f, 1.0f);
  n.highlight_deg = node.getInRange("highlight_deg", n.highlight_deg, 0.0f, 90.0f);
  n.highlight_dropout = node.getInRange("highlight_dropout", n.highlight_dropout, 0.0f, 1.0f);
  n.range_fade_start = node.getInRange("range_fade_start", n.range_fade_start, 0.0f, 1000.0f);
  n.range_fade_end = node.getInRange("range_fade_end", n.range_fade_end, 0.0f, 1000.0f);
  if (n.range_fade_end < n.range_fade_start)
    node["range_fade_end"].fail("range_fade_end >= range_fade_start", std::to_string(n.range_fade_end));
  n.edge_band_px = node.getInRange("edge_band_px", n.edge_band_px, 0.0f, 32.0f);
  n.low_texture_contrast = node.getInRange("low_texture_contrast", n.low_texture_contrast, 0.0f, 255.0f);
  n.low_texture_dropout = node.getInRange("low_texture_dropout", n.low_texture_dropout, 0.0f, 1.0f);
  n.edge_fattening_px = node.getInRange("edge_fattening_px", n.edge_fattening_px, 0.0f, 32.0f);
  n.hole_patch_px = node.getInRange("hole_patch_px", n.hole_patch_px, 1.0f, 256.0f);
  n.hole_flicker = node.getInRange("hole_flicker", n.hole_flicker, 0.0f, 1.0f);
}

SceneDescription builtin(const Builtin& b) {
  SceneDescription d;
  d.name = b.name;
  d.source = "built-in";
  d.hall = b.hall;
  d.relic = b.relic;
  d.visitors = b.visitors;
  d.close_visitors = b.close_visitors;
  return d;
}

SceneDescription loadSceneFile(const fs::path& path) {
  const ConfigNode root = ConfigNode::loadFile(path);
  if (!root.isMap()) root.fail("a map of scene settings (hall, relic, visitors, seed, camera, noise, ...)");
  static const std::set<std::string> known = {
      "base",           "hall",     "relic",         "fit_relic",         "relic_roughness",
      "relic_metallic", "visitors", "visitor_model", "close_visitors",    "seed",
      "camera",         "sensor",   "noise",         "panorama_position", "plinth"};
  for (const auto& key : root.keys())
    if (!known.count(key))
      root[key].fail(
          "one of base, hall, relic, fit_relic, relic_roughness, relic_metallic, visitors, visitor_model, "
          "close_visitors, seed, camera, sensor, noise, panorama_position, plinth",
          key);
  SceneDescription d;
  if (root.has("base")) {
    const auto base = root["base"].as<std::string>();
    const auto it = std::find_if(std::begin(kBuiltins), std::end(kBuiltins),
                                 [&](const Builtin& b) { return base == b.name; });
    if (it == std::end(kBuiltins))
      root["base"].fail("a built-in scene name (see `holopyramid scenes`)", base);
    d = builtin(*it);
  }
  d.name = path.stem().string();
  d.source = path.string();
  if (root.has("hall")) {
    d.hall = root["hall"].as<std::string>();
    const auto halls = hallNames();
    if (std::find(halls.begin(), halls.end(), d.hall) == halls.end())
      root["hall"].fail("one of room, gallery, atrium, window, none", d.hall);
  }
  if (root.has("relic")) {
    d.relic = root["relic"].as<std::string>();
    if (!isRelicName(d.relic)) {
      fs::path model = d.relic;
      if (model.is_relative()) model = path.parent_path() / model;
      const std::string ext = model.extension().string();
      if ((ext != ".gltf" && ext != ".glb") || !fs::exists(model))
        root["relic"].fail(
            relics::relicNameList() + " or an existing .gltf/.glb file (relative to the scene file)",
            d.relic);
      d.relic = model.string();
    }
  }
  d.fit_relic = root.get<bool>("fit_relic", d.fit_relic);
  if (root.has("relic_roughness")) d.relic_roughness = root.getInRange("relic_roughness", 0.0f, 0.0f, 1.0f);
  if (root.has("relic_metallic")) d.relic_metallic = root.getInRange("relic_metallic", 0.0f, 0.0f, 1.0f);
  if (root.has("visitors")) {
    d.visitors = root["visitors"].as<int>();
    if (d.visitors < 0 || d.visitors > 16)
      root["visitors"].fail("a visitor count in [0, 16]", std::to_string(d.visitors));
  }
  if (root.has("visitor_model")) {
    const auto name = root["visitor_model"].as<std::string>();
    const auto names = visitorModelNames();
    if (std::find(names.begin(), names.end(), name) == names.end())
      root["visitor_model"].fail("a visitor model: figures or bodies", name);
    d.visitor_model = visitorModelFromName(name);
  }
  if (root.has("close_visitors")) {
    d.close_visitors = root["close_visitors"].as<int>();
    if (d.close_visitors < 0 || d.close_visitors > 4)
      root["close_visitors"].fail("a count of visitors close to the pyramid in [0, 4]",
                                  std::to_string(d.close_visitors));
  }
  if (root.has("seed")) {
    const auto seed = root["seed"].as<double>();
    if (seed < 0 || seed != std::floor(seed) || seed > 9.007e15)
      root["seed"].fail("a non-negative integer seed");
    d.seed = static_cast<std::uint64_t>(seed);
  }
  if (root.has("camera")) readCamera(root["camera"], d.camera);
  if (root.has("sensor")) {
    const bool enabled = d.noise.enabled;
    const auto name = root["sensor"].as<std::string>();
    const auto names = sensorProfileNames();
    if (std::find(names.begin(), names.end(), name) == names.end())
      root["sensor"].fail("a sensor profile: uniform, structured-light or stereo", name);
    d.noise = sensorProfile(sensorProfileFromName(name));
    d.noise.enabled = enabled;
  }
  if (root.has("noise")) readNoise(root["noise"], d.noise);
  if (root.has("panorama_position")) {
    d.panorama_position = root["panorama_position"].as<vec3>();
    if (!isFinite(d.panorama_position)) root["panorama_position"].fail("three finite numbers (metres)");
  }
  if (root.has("plinth")) {
    d.plinth = parsePlinth(root["plinth"]);
  }
  return d;
}

mat4 cameraPose(int face, float tilt_deg) {
  const float a = static_cast<float>(face) * 0.5f * kPi;
  const vec3 out{std::sin(a), 0.0f, std::cos(a)};
  const vec3 eye = (kBaseHalfWidth + 0.005f) * out - vec3(0.0f, kCameraDrop, 0.0f);
  const float tilt = tilt_deg * kPi / 180.0f;
  return lookAtCameraToWorld(eye, eye + std::cos(tilt) * out + vec3(0.0f, std::sin(tilt), 0.0f));
}

const Material* materialAt(const Model& model, const RayScene& scene, const RayHit& hit) {
  const int material = scene.mesh(hit.geometry).material;
  if (material < 0 || material >= static_cast<int>(model.materials.size())) return nullptr;
  return &model.materials[static_cast<std::size_t>(material)];
}

// Radiance a ray sees at a hit: the material's emission (lighting is baked, see museum.hpp).
vec3 radianceAt(const Model& model, const RayScene& scene, const RayHit& hit) {
  const Material* m = materialAt(model, scene, hit);
  return m ? m->emission : vec3(0.0f);
}

}  // namespace

std::vector<std::string> builtinSceneNames() {
  std::vector<std::string> names;
  for (const auto& b : kBuiltins) names.emplace_back(b.name);
  return names;
}

std::vector<std::string> builtinRelicNames() {
  return relics::relicNames();
}

std::string describeBuiltinScene(const std::string& name) {
  for (const auto& b : kBuiltins)
    if (name == b.name) return b.what;
  return {};
}

SceneDescription loadScene(const std::string& name_or_file) {
  for (const auto& b : kBuiltins)
    if (name_or_file == b.name) return builtin(b);
  const fs::path path = name_or_file;
  const std::string ext = path.extension().string();
  if (ext == ".yaml" || ext == ".yml" || fs::is_regular_file(path)) {
    if (!fs::exists(path)) throw InputError(name_or_file, "", "an existing scene file", "not found");
    return loadSceneFile(path);
  }
  std::string names;
  for (const auto& b : kBuiltins) names += std::string(names.empty() ? "" : ", ") + b.name;
  throw InputError("", "scene", "a built-in scene (" + names + ") or a .yaml scene file", name_or_file);
}

struct Museum::Impl {
  SceneDescription description;
  Model hall;
  Model relic;
  std::vector<VisitorPlan> plans;
  std::vector<CameraModel> cameras;
  RayScene hall_scene;
  std::vector<vec3> plane_directions;  // z = 1 directions per pixel, shared by the cameras
};

Museum::Museum(SceneDescription description) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.description = std::move(description);
  const SceneDescription& d = m.description;
  const std::string origin = d.source.empty() ? "built-in" : d.source;
  m.hall = makeHall(d.hall, origin);
  if (isRelicName(d.relic)) {
    // Procedural relics travel through glTF like any model, so the loader sees them too.
    m.relic = loadGlbFromMemory(encodeGlb(relics::makeRelic(d.relic, origin)), d.relic + ".glb");
  } else {
    m.relic = loadGltf(d.relic);
  }
  for (auto& mat : m.relic.materials) {
    if (d.relic_roughness >= 0.0f) mat.roughness = std::min(d.relic_roughness, 1.0f);
    if (d.relic_metallic >= 0.0f) mat.metallic = std::min(d.relic_metallic, 1.0f);
  }
  if (d.fit_relic) relics::fitOnPedestal(m.relic);
  m.plans = planVisitors(d.visitors, d.seed, d.hall, d.visitor_model);
  if (d.close_visitors < 0 || d.close_visitors > 4)
    throw InputError(origin, "close_visitors", "a count in [0, 4]", std::to_string(d.close_visitors));
  for (const VisitorPlan& p : planCloseVisitors(d.close_visitors, d.seed, d.hall, d.visitor_model))
    m.plans.push_back(p);
  const auto& c = d.camera;
  const Intrinsics K =
      Intrinsics::fromFov(c.width, c.height, c.hfov_deg * kPi / 180.0f, c.vfov_deg * kPi / 180.0f);
  for (int f = 0; f < kFaceCount; ++f) m.cameras.emplace_back(K, cameraPose(f, c.tilt_deg));
  m.cameras.emplace_back(K, lookAtCameraToWorld(kCheckCameraEye, kCheckCameraTarget));
  m.plane_directions = m.cameras.front().planeDirectionTable();
  for (const auto& mesh : m.hall.meshes) m.hall_scene.addMesh(mesh);
  m.hall_scene.commit();
}

Museum::~Museum() = default;
Museum::Museum(Museum&&) noexcept = default;
Museum& Museum::operator=(Museum&&) noexcept = default;

const SceneDescription& Museum::description() const {
  return impl_->description;
}
const CameraModel& Museum::camera(int index) const {
  return impl_->cameras.at(static_cast<std::size_t>(index));
}
float Museum::frameTime(int frame) const {
  return static_cast<float>(frame) / impl_->description.camera.fps;
}
const Model& Museum::relic() const {
  return impl_->relic;
}
const Model& Museum::hall() const {
  return impl_->hall;
}
Model Museum::visitors(int frame) const {
  return buildVisitors(impl_->plans, frameTime(frame));
}

std::vector<vec3> Museum::visitorHeads(int frame) const {
  std::vector<vec3> heads;
  for (const auto& p : impl_->plans) heads.push_back(poseAt(p, frameTime(frame)).head);
  return heads;
}

SimulatedFrame Museum::renderCamera(int index, int frame, bool with_visitors, double time_offset_s) const {
  const Impl& m = *impl_;
  const CameraModel& cam = camera(index);
  const CameraSettings& settings = m.description.camera;
  const Model people =
      with_visitors ? buildVisitors(m.plans, frameTime(frame) + static_cast<float>(time_offset_s)) : Model{};
  RayScene people_scene;
  for (const auto& mesh : people.meshes) people_scene.addMesh(mesh);
  people_scene.commit();

  const int W = cam.width(), H = cam.height();
  cv::Mat depth = cv::Mat::zeros(H, W, CV_32FC1);
  cv::Mat cosine = cv::Mat::zeros(H, W, CV_32FC1);
  cv::Mat radiance = cv::Mat::zeros(H, W, CV_32FC3);
  cv::Mat foreground = cv::Mat::zeros(H, W, CV_8UC1);
  SurfaceMaps surface{cv::Mat::zeros(H, W, CV_32FC1), cv::Mat::zeros(H, W, CV_32FC1),
                      cv::Mat::ones(H, W, CV_32FC1)};
  const mat3 R(cam.T_world_camera());
  const vec3 origin = cam.position();
  tbb::parallel_for(0, H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      const vec3 plane = m.plane_directions[static_cast<std::size_t>(y * W + x)];
      const float norm = glm::length(plane);
      const Ray ray{origin, R * (plane / norm)};
      RayHit hit = m.hall_scene.intersect(ray);
      const RayScene* scene = &m.hall_scene;
      const Model* model = &m.hall;
      const RayHit person = people_scene.meshCount() > 0 ? people_scene.intersect(ray) : RayHit{};
      if (person.hit() && (!hit.hit() || person.t < hit.t)) {
        hit = person;
        scene = &people_scene;
        model = &people;
        foreground.at<std::uint8_t>(y, x) = 255;
      }
      if (!hit.hit()) continue;
      if (const Material* material = materialAt(*model, *scene, hit)) {
        setRgb(radiance, x, y, material->emission);
        const vec3& c = material->base_colour;
        surface.albedo.at<float>(y, x) = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
        surface.metallic.at<float>(y, x) = material->metallic;
        surface.roughness.at<float>(y, x) = material->roughness;
      }
      const float z = hit.t / norm;  // camera-frame depth of a point t along the unit ray
      if (z >= settings.min_range && z <= settings.max_range) depth.at<float>(y, x) = z;
      cosine.at<float>(y, x) = std::abs(glm::dot(ray.direction, hit.geometric_normal));
    }
  });
  const std::uint64_t stream = with_visitors ? static_cast<std::uint64_t>(frame) : kBackgroundFrame;
  const std::uint64_t seed =
      m.description.seed * 0x100000001B3ull + static_cast<std::uint64_t>(index) * 0x9E3779B9ull + stream;
  const std::uint64_t static_seed = m.description.seed * 0x100000001B3ull +
                                    static_cast<std::uint64_t>(index) * 0x9E3779B9ull + kBackgroundFrame;
  SensorOutput sensed = applySensorNoise(m.description.noise, settings, depth, cosine, radiance, seed,
                                         static_seed ^ 0x57a71cull, surface);

  SimulatedFrame out;
  out.frame.colour = sensed.colour;
  out.frame.depth = sensed.depth;
  out.frame.camera_id = index;
  out.frame.sequence = static_cast<std::uint64_t>(std::max(frame, 0));
  out.frame.device_time = Nanoseconds(std::llround(1e9 * frame / static_cast<double>(settings.fps)));
  out.true_depth = depth;
  out.foreground = foreground;
  return out;
}

RgbdFrame Museum::backgroundFrame(int index) const {
  return renderCamera(index, 0, false).frame;
}

cv::Mat Museum::renderPanorama(int width, int height) const {
  if (width <= 0 || height <= 0) throw Error("renderPanorama: the size must be positive");
  const Impl& m = *impl_;
  cv::Mat pano = cv::Mat::zeros(height, width, CV_32FC3);
  // 2 x 2 fixed sub-pixel samples: smooth edges, still deterministic.
  const float offsets[2] = {0.25f, 0.75f};
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      vec3 sum(0.0f);
      for (float oy : offsets)
        for (float ox : offsets) {
          const vec2 uv{(static_cast<float>(x) + ox) / static_cast<float>(width),
                        (static_cast<float>(y) + oy) / static_cast<float>(height)};
          const Ray ray{m.description.panorama_position, equirect::uvToDirection(uv)};
          const RayHit hit = m.hall_scene.intersect(ray);
          if (hit.hit()) sum += radianceAt(m.hall, m.hall_scene, hit);
        }
      setRgb(pano, x, y, 0.25f * sum);
    }
  });
  return pano;
}

}  // namespace holo::sim
