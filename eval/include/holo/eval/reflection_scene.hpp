// What `holopyramid render` and `holopyramid eval reflections` share: turning --scene, --relic,
// --panorama and the view options into a relic, its emitters, an environment and a camera, and
// rendering one view with a named method. Units: metres, degrees where the name says so.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "holo/core/camera_model.hpp"
#include "holo/core/mesh.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"

namespace holo::app {

struct SceneOptions {
  std::string scene = "empty";   // built-in scene name or YAML file; "empty" = relic alone
  std::string relic;             // built-in relic name or glTF file; empty = the scene's
  std::string hall;              // built-in hall name; empty = the scene's
  std::string panorama;          // HDR/EXR file; empty = the museum's rendered hall panorama
  bool fit = false;              // scale and centre a relic file on the pedestal
  int frame = 0;                 // museum frame (visitor poses)
  int close_visitors = -1;       // visitors standing close to the pyramid (sim); -1 = the scene's
  float camera_vfov_deg = 0.0f;  // the depth cameras' vertical field of view; 0 = the scene's
  float camera_tilt_deg = 0.0f;  // the depth cameras' upwards tilt; 0 = the scene's
  void addTo(CLI::App& app);
};

struct ViewOptions {
  int width = 256, height = 256;
  int face = 0;
  std::string eye, look_at;  // "X,Y,Z" (metres); empty = the face's default eye / relic centre
  float fov_deg = 0.0f;      // vertical; 0 = frame the relic
  void addTo(CLI::App& app);
};

// The relic, the real things around it (emitters) and the environment beyond.
struct ReflectionScene {
  std::string scene_name, relic_name;
  Model relic;
  std::vector<Model> static_emitters;       // the hall
  Model visitors;                           // visitors and what they carry at the frame (may be empty)
  cv::Mat panorama;                         // linear HDR CV_32FC3 BGR, the static environment
  depthfilter::ForegroundCloud foreground;  // the visitors as the depth cameras see them
  std::vector<reflect::ForegroundCameraImage> foreground_cameras;  // their colour and mask, per camera
  float floor_y = -1.0f;
  std::uint64_t hash = 0;  // of everything that changes the ground truth (for caching)
};

ReflectionScene loadReflectionScene(const SceneOptions& options);

// The view where visitors matter most: among the frames of the first ten seconds (every third of
// a second) and the four faces, the one where the most mirror-reflected rays from the relic (one
// per pixel of a 48^2 face view) meet the real visitors' geometry. Neutral to every method (true
// geometry, no renderer); "the face on the nearest visitor's side" left most views with no
// foreground reflection at all (docs/tracer.md).
struct VisitorView {
  int frame = 0, face = 0;
  float reflected_fraction = 0.0f;  // of the relic's pixels whose mirror ray meets a visitor
};
VisitorView visitorView(const SceneOptions& options);
CameraModel viewCamera(const ViewOptions& view, const ReflectionScene& scene);

inline const std::vector<std::string>& reflectionMethods() {
  static const std::vector<std::string> methods = {"gt", "ibl", "ibl-baseline", "ours", "ssrt", "mcpt"};
  return methods;
}

struct MethodSettings {
  int spp = 256;               // gt, mcpt: samples per pixel; ssrt: reflected rays per hit point
  int ibl_levels = 10;         // ibl*: roughness levels (PrefilterOptions::levels)
  int ibl_texel_density = 20;  // ibl*: PrefilterOptions::texel_density
  bool with_visitors = true;
  std::uint64_t seed = 1;
  reflect::TracerSettings tracer;  // ours: anti-aliasing, pyramid levels, voxel grid
  // ours, ssrt: the static hall's prefiltered panorama. The hall does not move, so it is built once
  // per scene (staticIbl) and not counted in the per-view time; null = build it here (reported
  // in build_ms, outside ms).
  std::shared_ptr<const reflect::PrefilteredIbl> static_ibl;
};

// The static panorama prefiltered with settings' levels and samples (what static_ibl holds).
std::shared_ptr<const reflect::PrefilteredIbl> staticIbl(const ReflectionScene& scene,
                                                         const MethodSettings& settings);

struct MethodResult {
  cv::Mat image;        // linear HDR CV_32FC3 BGR
  double ms = 0;        // render time of the view (ibl-baseline, and ibl without static_ibl: the
                        // prefilter build included; ours: the frame's voxel grid and pyramids
                        // included; mcpt: the voxel scene's build included)
  double build_ms = 0;  // IBL, mcpt: part of ms spent building maps or the scene; ours, ssrt:
                        // the static IBL built here when settings.static_ibl was null (not in ms)
  std::vector<std::pair<std::string, double>> passes;  // ours: ms per pass (frame passes first)
  double frame_ms = 0;  // ours: the per-frame passes (voxel grid, pyramids), shared by all views
  double view_ms = 0;   // ours: the per-view passes (hit points, static, walk, composition, tone map)
};

// Throws InputError(field "method") for an unknown method.
MethodResult renderMethod(const std::string& method, const ReflectionScene& scene, const CameraModel& camera,
                          const MethodSettings& settings, bool quiet = true);

// The path-traced ground truth ("gt", seed 1) of this scene and view, from the cache folder when
// it is there (keyed by the scene hash, the view bit for bit, the spp and the visitors), else
// rendered and stored there.
cv::Mat cachedGroundTruth(const ReflectionScene& scene, const CameraModel& camera, int spp,
                          bool with_visitors, const std::filesystem::path& cache);

// An HDR image as the pyramid displays it: tone-mapped (Reinhard, sRGB) at `exposure`, as floats
// in [0, 1] (CV_32FC3), the form fg_mse is computed on (eval tracer, bench accuracy).
cv::Mat displayedImage(const cv::Mat& hdr, float exposure);

// Writes a CV_8UC3 PNG atomically.
void writePng(const std::filesystem::path& path, const cv::Mat& bgr8);
// Writes FILE.exr and, beside it, FILE.png (tone mapped with `exposure`, auto when <= 0).
void writeImagePair(const std::string& exr_path, const cv::Mat& hdr, float exposure = 0.0f);

}  // namespace holo::app
