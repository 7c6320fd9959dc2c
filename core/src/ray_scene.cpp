#include "holo/core/ray_scene.hpp"

#include <algorithm>
#include <cstring>
#include <mutex>
#include <string>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/core/stats.hpp"

namespace holo {

namespace {
void embreeError(void*, RTCError code, const char* message) {
  stats::add("Embree/Errors");
  HOLO_LOG_ERROR("Embree error {}: {}", static_cast<int>(code), message ? message : "");
}

// Embree hands filter functions the context of the query: this one carries the query's mode.
struct QueryContext {
  RTCIntersectContext embree;  // first: Embree sees a plain context
  PartialHits partial = PartialHits::Stochastic;
};

// A uniform number in [0, 1) from the ray and the candidate hit (a murmur3-style finaliser over
// their bits).
float hitHash(const Ray& ray, const RayHit& hit) {
  std::uint64_t h = 0x9e3779b97f4a7c15ull;
  const auto mix = [&h](float value) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &value, sizeof(bits));
    h ^= bits;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
  };
  for (int k = 0; k < 3; ++k) {
    mix(ray.origin[k]);
    mix(ray.direction[k]);
  }
  mix(hit.barycentric.x);
  mix(hit.barycentric.y);
  h ^= std::uint64_t(hit.primitive) * 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 29;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 32;
  return float(h >> 40) * (1.0f / 16777216.0f);
}

void opacityFilter(const RTCFilterFunctionNArguments* args) {
  const auto& opacity = *static_cast<const HitOpacity*>(args->geometryUserPtr);
  const auto* query = reinterpret_cast<const QueryContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    Ray ray;
    ray.origin = {RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                  RTCRayN_org_z(args->ray, args->N, i)};
    ray.direction = {RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                     RTCRayN_dir_z(args->ray, args->N, i)};
    RayHit hit;
    hit.t = RTCRayN_tfar(args->ray, args->N, i);
    hit.geometry = RTCHitN_geomID(args->hit, args->N, i);
    hit.primitive = RTCHitN_primID(args->hit, args->N, i);
    hit.barycentric = {RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)};
    const vec3 ng(RTCHitN_Ng_x(args->hit, args->N, i), RTCHitN_Ng_y(args->hit, args->N, i),
                  RTCHitN_Ng_z(args->hit, args->N, i));
    const float len = glm::length(ng);
    hit.geometric_normal = len > 0.0f ? ng / len : -ray.direction;
    const float o = opacity(ray, hit);
    bool stops = o >= 1.0f;
    if (!stops && o > 0.0f)
      stops = (query != nullptr && query->partial == PartialHits::Solid) || hitHash(ray, hit) < o;
    if (!stops) args->valid[i] = 0;
  }
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

void RayScene::setHitOpacity(std::uint32_t geometry, HitOpacity opacity) {
  RTCGeometry g = geometries_.at(geometry);
  rtcSetGeometryUserData(g, &opacities_.emplace_back(std::move(opacity)));
  rtcSetGeometryIntersectFilterFunction(g, opacityFilter);
  rtcSetGeometryOccludedFilterFunction(g, opacityFilter);
  rtcCommitGeometry(g);
}

void RayScene::commit() {
  rtcCommitScene(scene_);
}

RayHit RayScene::intersect(const Ray& ray, float tmin, float tmax, PartialHits partial) const {
  QueryContext context;
  rtcInitIntersectContext(&context.embree);
  context.partial = partial;
  RTCRayHit rh = makeRayHit(ray, tmin, tmax);
  rtcIntersect1(scene_, &context.embree, &rh);
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

namespace {

// Casts rays[first, first + n) as one packet of Width rays (n <= Width) into hits.
template <int Width, typename Packet>
void castPacket(RTCScene scene, RTCIntersectContext& context, std::span<const Ray> rays,
                std::span<RayHit> hits, std::size_t first, int n, float tmin, float tmax) {
  alignas(64) int valid[Width];
  alignas(64) Packet packet;
  for (int i = 0; i < Width; ++i) {
    const bool used = i < n;
    valid[i] = used ? -1 : 0;
    const Ray& ray = rays[first + static_cast<std::size_t>(used ? i : 0)];
    packet.ray.org_x[i] = ray.origin.x;
    packet.ray.org_y[i] = ray.origin.y;
    packet.ray.org_z[i] = ray.origin.z;
    packet.ray.dir_x[i] = ray.direction.x;
    packet.ray.dir_y[i] = ray.direction.y;
    packet.ray.dir_z[i] = ray.direction.z;
    packet.ray.tnear[i] = tmin;
    packet.ray.tfar[i] = tmax;
    packet.ray.time[i] = 0.0f;
    packet.ray.mask[i] = 0xFFFFFFFFu;
    packet.ray.id[i] = static_cast<unsigned>(i);
    packet.ray.flags[i] = 0;
    packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    packet.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  if constexpr (Width == 16)
    rtcIntersect16(valid, scene, &context, &packet);
  else
    rtcIntersect8(valid, scene, &context, &packet);
  for (int i = 0; i < n; ++i) {
    RayHit& hit = hits[first + static_cast<std::size_t>(i)];
    hit = RayHit{};
    if (packet.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
    const vec3& direction = rays[first + static_cast<std::size_t>(i)].direction;
    hit.t = packet.ray.tfar[i];
    hit.geometry = packet.hit.geomID[i];
    hit.primitive = packet.hit.primID[i];
    hit.barycentric = {packet.hit.u[i], packet.hit.v[i]};
    vec3 ng(packet.hit.Ng_x[i], packet.hit.Ng_y[i], packet.hit.Ng_z[i]);
    const float len = glm::length(ng);
    ng = len > 0 ? ng / len : -direction;
    hit.geometric_normal = glm::dot(ng, direction) > 0 ? -ng : ng;
  }
}

}  // namespace

int RayScene::nativePacketWidth() {
  static const int width =
      rtcGetDeviceProperty(embreeDevice(), RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0 ? 16 : 8;
  return width;
}

void RayScene::setPacketWidth(int width) {
  if (width != 8 && width != 16)
    throw Error("RayScene::setPacketWidth: expected 8 or 16 rays, got " + std::to_string(width));
  packet_width_ = width;
}

void RayScene::intersectPackets(std::span<const Ray> rays, std::span<RayHit> hits, RayCoherence coherence,
                                float tmin, float tmax, PartialHits partial) const {
  if (rays.size() != hits.size())
    throw Error("RayScene::intersectPackets: " + std::to_string(rays.size()) + " rays for " +
                std::to_string(hits.size()) + " hits");
  QueryContext context;
  rtcInitIntersectContext(&context.embree);
  context.embree.flags = coherence == RayCoherence::Coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                                             : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  context.partial = partial;
  const std::size_t width = static_cast<std::size_t>(packet_width_);
  for (std::size_t first = 0; first < rays.size(); first += width) {
    const int n = static_cast<int>(std::min(width, rays.size() - first));
    if (packet_width_ == 16)
      castPacket<16, RTCRayHit16>(scene_, context.embree, rays, hits, first, n, tmin, tmax);
    else
      castPacket<8, RTCRayHit8>(scene_, context.embree, rays, hits, first, n, tmin, tmax);
  }
}

bool RayScene::occluded(const Ray& ray, float tmin, float tmax) const {
  QueryContext context;
  rtcInitIntersectContext(&context.embree);
  RTCRay r = makeRayHit(ray, tmin, tmax).ray;
  rtcOccluded1(scene_, &context.embree, &r);
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
