#include "holo/eval/ground_truth_cache.hpp"

#include <cstdio>
#include <string_view>
#include <type_traits>

#include "holo/core/hdr_io.hpp"
#include "holo/eval/methods.hpp"

namespace holo::eval {
namespace {

// 64-bit FNV-1a over every byte that changes the truth, fed in a fixed order with each
// variable-length part's size first, so that no two different inputs run together alike.
class KeyHash {
 public:
  void bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) h_ = (h_ ^ p[i]) * 1099511628211ull;
  }
  template <typename T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  template <typename T>
  void array(const std::vector<T>& v) {
    value(v.size());
    bytes(v.data(), v.size() * sizeof(T));
  }
  void text(std::string_view s) {
    value(s.size());
    bytes(s.data(), s.size());
  }
  void image(const cv::Mat& m) {
    value(m.rows);
    value(m.cols);
    value(m.type());
    for (int y = 0; y < m.rows; ++y) bytes(m.ptr(y), m.cols * m.elemSize());
  }
  void model(const Model& model) {
    value(model.meshes.size());
    for (const TriangleMesh& mesh : model.meshes) {
      array(mesh.positions);
      array(mesh.normals);
      array(mesh.tangents);
      array(mesh.uvs);
      array(mesh.uvs1);
      array(mesh.triangles);
      value(mesh.material);
    }
    value(model.materials.size());
    for (const Material& m : model.materials) {
      // Every field, rendered today or not: a renderer that starts reading one re-keys nothing.
      value(m.base_colour);
      value(m.alpha);
      value(m.metallic);
      value(m.roughness);
      value(m.emission);
      value(m.base_colour_texture);
      value(m.metallic_roughness_texture);
      value(m.emissive_texture);
      value(m.normal_texture);
      value(m.normal_scale);
      value(m.occlusion_texture);
      value(m.occlusion_strength);
      value(m.alpha_mode);
      value(m.alpha_cutoff);
      value(m.double_sided);
      value(m.specular);
      value(m.specular_colour);
      value(m.specular_texture);
      value(m.specular_colour_texture);
      value(m.clearcoat);
      value(m.clearcoat_roughness);
      value(m.clearcoat_texture);
      value(m.clearcoat_roughness_texture);
      value(m.clearcoat_normal_texture);
      value(m.clearcoat_normal_scale);
      value(m.transmission);
      value(m.transmission_texture);
      value(m.thickness);
      value(m.thickness_texture);
      value(m.attenuation_colour);
      value(m.attenuation_distance);
      value(m.ior);
    }
    value(model.textures.size());
    for (const Texture& texture : model.textures) {
      image(texture.image());  // the mip chain is built from it
      value(texture.sampler);
      value(texture.encoding);  // sRGB texels are filtered in linear light
    }
  }
  std::uint64_t digest() const { return h_; }

 private:
  std::uint64_t h_ = 1469598103934665603ull;
};

}  // namespace

std::string groundTruthKey(const ReflectionScene& scene, const CameraModel& camera, int spp,
                           bool with_visitors, std::uint64_t seed, int tracer_version) {
  KeyHash h;
  h.value(tracer_version);
  h.model(scene.relic);
  h.value(scene.static_emitters.size());
  for (const Model& emitter : scene.static_emitters) h.model(emitter);
  h.value(with_visitors);
  if (with_visitors) h.model(scene.visitors);
  h.image(scene.panorama);
  h.value(camera.T_world_camera());
  h.value(camera.intrinsics());
  h.value(camera.width());
  h.value(camera.height());
  h.value(spp);
  h.value(seed);
  char name[96];
  std::snprintf(name, sizeof name, "gt-%016llx-%dx%d-spp%d.exr", static_cast<unsigned long long>(h.digest()),
                camera.width(), camera.height(), spp);
  return name;
}

cv::Mat cachedGroundTruth(const ReflectionScene& scene, const CameraModel& camera, int spp,
                          bool with_visitors, const std::filesystem::path& cache) {
  MethodSettings s;
  s.spp = spp;
  s.with_visitors = with_visitors;
  const std::filesystem::path file = cache / groundTruthKey(scene, camera, spp, with_visitors, s.seed);
  if (std::filesystem::exists(file)) {
    const cv::Mat cached = loadHdr(file).pixels;
    if (cached.cols == camera.width() && cached.rows == camera.height()) return cached;
  }
  const cv::Mat image = renderMethod("gt", scene, camera, s, false).image;
  std::filesystem::create_directories(cache);
  saveHdr(file, image);
  return image;
}

}  // namespace holo::eval
