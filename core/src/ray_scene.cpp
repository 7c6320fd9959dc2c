#include "holo/core/ray_scene.hpp"

#include <mutex>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/core/stats.hpp"

namespace holo {

namespace {
void embreeError(void*, RTCError code, const char* message) {
  stats::add("Embree/Errors");
  HOLO_LOG_ERROR("Embree error {}: {}", static_cast<int>(code), message ? message : "");
}

RTCRayHit makeRayHit(const Ray& ray, float tmin, float tmax) {
  RTCRayHit rh{};
  rh.ray.org_x = ray.origin.x;
  rh.ray.org_y = ray.origin.y;
  rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.direction.x;
  rh.ray.dir_y = ray.direction.y;
  rh.ray.dir_z = ray.direction.z;
  rh.ray.tnear = tmin;
  rh.ray.tfar = tmax;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}
}  // namespace

RTCDevice embreeDevice() {
  static RTCDevice device = [] {
    RTCDevice d = rtcNewDevice(nullptr);
    if (!d)
      throw Error("Embree: could not create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) +
                  ")");
    rtcSetDeviceErrorFunction(d, embreeError, nullptr);
    return d;
  }();
  return device;
}

RayScene::RayScene() : scene_(rtcNewScene(embreeDevice())) {
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
}

RayScene::~RayScene() {
  for (auto g : geometries_) rtcReleaseGeometry(g);
  rtcReleaseScene(scene_);
}

std::uint32_t RayScene::addMesh(const TriangleMesh& mesh) {
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      if (t[k] >= mesh.positions.size()) throw Error("mesh '" + mesh.name + "': triangle index out of range");
  auto& stored = meshes_.emplace_back(mesh);
  RTCGeometry geometry = rtcNewGeometry(embreeDevice(), RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree may read up to 16 bytes past the last vertex with SSE loads: vec3 arrays need one
  // float of padding, which the vector's capacity provides.
  stored.positions.reserve(stored.positions.size() + 1);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, stored.positions.data(),
                             0, sizeof(vec3), stored.positions.size());
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, stored.triangles.data(), 0,
                             sizeof(uvec3), stored.triangles.size());
  rtcCommitGeometry(geometry);
  const std::uint32_t id = rtcAttachGeometry(scene_, geometry);
  geometries_.push_back(geometry);
  HOLO_ASSERT(id + 1 == geometries_.size());
  return id;
}

void RayScene::updatePositions(std::uint32_t geometry, const std::vector<vec3>& positions) {
  auto& stored = meshes_.at(geometry);
  if (positions.size() != stored.positions.size()) throw Error("updatePositions: vertex count changed");
  std::copy(positions.begin(), positions.end(), stored.positions.begin());
  rtcUpdateGeometryBuffer(geometries_[geometry], RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(geometries_[geometry]);
}

void RayScene::commit() {
  rtcCommitScene(scene_);
}

RayHit RayScene::intersect(const Ray& ray, float tmin, float tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = makeRayHit(ray, tmin, tmax);
  rtcIntersect1(scene_, &context, &rh);
  RayHit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.t = rh.ray.tfar;
  hit.geometry = rh.hit.geomID;
  hit.primitive = rh.hit.primID;
  hit.barycentric = {rh.hit.u, rh.hit.v};
  vec3 n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  const float len = glm::length(n);
  n = len > 0 ? n / len : -ray.direction;
  hit.geometric_normal = glm::dot(n, ray.direction) > 0 ? -n : n;
  return hit;
}

bool RayScene::occluded(const Ray& ray, float tmin, float tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r = makeRayHit(ray, tmin, tmax).ray;
  rtcOccluded1(scene_, &context, &r);
  return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

vec3 RayScene::shadingNormal(const RayHit& hit, const vec3& ray_direction) const {
  const auto& mesh = meshes_.at(hit.geometry);
  if (mesh.normals.empty()) return hit.geometric_normal;
  const auto& t = mesh.triangles[hit.primitive];
  const float u = hit.barycentric.x, v = hit.barycentric.y;
  vec3 n = (1.0f - u - v) * mesh.normals[t.x] + u * mesh.normals[t.y] + v * mesh.normals[t.z];
  const float len = glm::length(n);
  if (!(len > 1e-12f)) return hit.geometric_normal;
  n /= len;
  return glm::dot(n, ray_direction) > 0 ? -n : n;
}

vec2 RayScene::uv(const RayHit& hit) const {
  const auto& mesh = meshes_.at(hit.geometry);
  if (mesh.uvs.empty()) return vec2(0.0f);
  const auto& t = mesh.triangles[hit.primitive];
  const float u = hit.barycentric.x, v = hit.barycentric.y;
  return (1.0f - u - v) * mesh.uvs[t.x] + u * mesh.uvs[t.y] + v * mesh.uvs[t.z];
}

}  // namespace holo
