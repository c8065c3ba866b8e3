#include "accel.hpp"

#include <embree3/rtcore.h>

#include <limits>
#include <string>

#include "skin/util/error.hpp"

namespace skin::render {

struct Accel::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

Accel::Accel(const SceneData& data) : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice("verbose=0");
  if (!impl_->device) throw std::runtime_error("Embree: cannot create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (std::size_t mi = 0; mi < data.meshes.size(); ++mi) {
    const Mesh& m = data.meshes[mi];
    RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), m.position.size()));
    for (std::size_t i = 0; i < m.position.size(); ++i) {
      const Vec3& p = m.position[i];
      v[3 * i] = static_cast<float>(p.x);
      v[3 * i + 1] = static_cast<float>(p.y);
      v[3 * i + 2] = static_cast<float>(p.z);
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), m.triangles.size()));
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      for (std::size_t k = 0; k < 3; ++k) idx[3 * t + k] = m.triangles[t][k];
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(impl_->scene, g, static_cast<unsigned>(mi));
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(impl_->scene);
  const RTCError err = rtcGetDeviceError(impl_->device);
  if (err != RTC_ERROR_NONE) throw std::runtime_error("Embree: scene build failed (error " + std::to_string(static_cast<int>(err)) + ")");
  if (!data.meshes.empty()) extent_ = std::max(1e-6, length(hi - lo));
}

Accel::~Accel() = default;

namespace {
void fill_ray(RTCRay& r, const Vec3& o, const Vec3& d, double t_min, double t_max) {
  r.org_x = static_cast<float>(o.x);
  r.org_y = static_cast<float>(o.y);
  r.org_z = static_cast<float>(o.z);
  r.dir_x = static_cast<float>(d.x);
  r.dir_y = static_cast<float>(d.y);
  r.dir_z = static_cast<float>(d.z);
  r.tnear = static_cast<float>(t_min);
  r.tfar = t_max >= static_cast<double>(std::numeric_limits<float>::max()) ? std::numeric_limits<float>::infinity()
                                                                            : static_cast<float>(t_max);
  r.time = 0;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
}
}  // namespace

bool Accel::intersect(const Vec3& o, const Vec3& d, double t_min, double t_max, RayHit* hit) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  fill_ray(rh.ray, o, d, t_min, t_max);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit->t = rh.ray.tfar;
  hit->mesh = rh.hit.geomID;
  hit->prim = rh.hit.primID;
  hit->b1 = rh.hit.u;
  hit->b2 = rh.hit.v;
  return true;
}

bool Accel::occluded(const Vec3& o, const Vec3& d, double t_min, double t_max) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  fill_ray(r, o, d, t_min, t_max);
  rtcOccluded1(impl_->scene, &ctx, &r);
  return r.tfar < 0;  // Embree sets tfar to -inf on a hit
}

}  // namespace skin::render
