#pragma once
// Ray queries over the scene's triangles (Embree 3 behind a pimpl: no Embree type escapes).
#include <cstdint>
#include <memory>

#include "scene_data.hpp"

namespace skin::render {

struct RayHit {
  double t = 0;
  std::uint32_t mesh = 0, prim = 0;
  double b1 = 0, b2 = 0;  // barycentrics of vertices 1 and 2
};

class Accel {
 public:
  explicit Accel(const SceneData& scene);
  ~Accel();
  Accel(const Accel&) = delete;
  Accel& operator=(const Accel&) = delete;
  // Closest hit with t in (t_min, t_max); `d` need not be unit length (t is in units of |d|).
  bool intersect(const Vec3& o, const Vec3& d, double t_min, double t_max, RayHit* hit) const;
  bool occluded(const Vec3& o, const Vec3& d, double t_min, double t_max) const;
  double extent() const { return extent_; }  // bounding box diagonal [scene units]

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double extent_ = 1;
};

}  // namespace skin::render
