#pragma once
// Lights of a scene (internal; docs/renderer.md, "Lights"). Every light type has one `sample` and
// one `pdf` that share the geometry they are computed from, so the density next-event estimation
// divides by and the density MIS weighs a BSDF-sampled hit with are the same function:
//
//   LightSample sample(p, n, u)  a direction from the point p (shading normal n) toward the light,
//                                its incident radiance and its solid-angle density;
//   double pdf(p, n, wi)         that density for any direction wi [1/sr] (0 where `sample` never
//                                goes, and 0 for delta lights, which no ray can hit);
//   bool intersect(o, d, &t)     area lights: the nearest point of the light along a ray;
//   Rgb3 Le()                    area lights: the radiance they emit.
//
// The receiving normal n matters only for the constant environment (sampled cosine-weighted
// about it); the other lights ignore it. Tested in tests/render/test_lights.cpp (chi-square of
// each sampler against its pdf, pdfs integrating to one over their solid angle).
#include <iosfwd>
#include <limits>
#include <memory>
#include <variant>

#include "skin/render/math.hpp"
#include "skin/render/sampling.hpp"

namespace skin::render {

struct Texture;
}  // namespace skin::render
namespace skin::color {
class Illuminant;
}
namespace skin::render {

struct LightSample {
  Rgb3 L;      // incident radiance; delta lights: intensity / d^2 (point) or irradiance
  Vec3 wi;     // unit, toward the light
  double dist = std::numeric_limits<double>::infinity();  // to the light along wi (scene units)
  double pdf = 0;  // solid angle [1/sr]; delta lights: 1 (the light itself is the choice); 0 = none
  bool delta = false;
};

// A point emitting `intensity` in every direction (radiance-like units / sr).
struct PointLight {
  Vec3 position;
  Rgb3 intensity;
  LightSample sample(const Vec3& p, const Vec3& n, Vec2 u) const;
  double pdf(const Vec3&, const Vec3&, const Vec3&) const { return 0.0; }
  bool intersect(const Vec3&, const Vec3&, double*) const { return false; }
  Rgb3 Le() const { return {}; }
};

// Parallel light travelling along `direction` (unit) with `irradiance` on a surface facing it.
struct DirectionalLight {
  Vec3 direction;
  Rgb3 irradiance;
  LightSample sample(const Vec3& p, const Vec3& n, Vec2 u) const;
  double pdf(const Vec3&, const Vec3&, const Vec3&) const { return 0.0; }
  bool intersect(const Vec3&, const Vec3&, double*) const { return false; }
  Rgb3 Le() const { return {}; }
};

// A sphere of uniform radiance, sampled uniformly in the cone it subtends from p (pdf
// 1 / (2 pi (1 - cos theta_max)) inside the cone, 0 outside; no sample from inside the sphere).
struct SphereLight {
  Vec3 centre;
  double radius = 0;
  Rgb3 radiance;
  LightSample sample(const Vec3& p, const Vec3& n, Vec2 u) const;
  double pdf(const Vec3& p, const Vec3& n, const Vec3& wi) const;
  bool intersect(const Vec3& o, const Vec3& d, double* t) const;
  Rgb3 Le() const { return radiance; }

  // The cone of directions from p: axis toward the centre, cos theta_max; false inside.
  struct Cone {
    Vec3 to_centre;        // centre - p
    double dist2 = 0;      // |centre - p|^2
    double cos_max = 1;
  };
  bool cone(const Vec3& p, Cone* c) const;
};

// A one-sided parallelogram corner + s edge_u + t edge_v, (s, t) in [0, 1]^2, emitting toward
// cross(edge_u, edge_v); sampled uniformly by area, converted to solid angle by
// pdf = d^2 / (cos theta_light A).
struct QuadLight {
  Vec3 corner, edge_u, edge_v;
  Rgb3 radiance;
  LightSample sample(const Vec3& p, const Vec3& n, Vec2 u) const;
  double pdf(const Vec3& p, const Vec3& n, const Vec3& wi) const;
  bool intersect(const Vec3& o, const Vec3& d, double* t) const;
  Rgb3 Le() const { return radiance; }
  double area() const { return length(cross(edge_u, edge_v)); }
  Vec3 normal() const { return normalize(cross(edge_u, edge_v)); }
  // The area-to-solid-angle density of a point at squared distance dist2 seen at cos theta_light:
  // the one conversion both `sample` and `pdf` use.
  double solid_angle_pdf(double dist2, double cos_light) const {
    return cos_light > 0 ? dist2 / (cos_light * area()) : 0.0;
  }
};

// One light of the scene, of any type; callers use the interface above and never the type.
class Light {
 public:
  using Shape = std::variant<PointLight, DirectionalLight, SphereLight, QuadLight>;
  Light(Shape shape) : shape_(std::move(shape)) {}  // NOLINT(google-explicit-constructor)
  LightSample sample(const Vec3& p, const Vec3& n, Vec2 u) const {
    return std::visit([&](const auto& l) { return l.sample(p, n, u); }, shape_);
  }
  double pdf(const Vec3& p, const Vec3& n, const Vec3& wi) const {
    return std::visit([&](const auto& l) { return l.pdf(p, n, wi); }, shape_);
  }
  bool intersect(const Vec3& o, const Vec3& d, double* t) const {
    return std::visit([&](const auto& l) { return l.intersect(o, d, t); }, shape_);
  }
  Rgb3 Le() const {
    return std::visit([](const auto& l) { return l.Le(); }, shape_);
  }
  const Shape& shape() const { return shape_; }
  // The CIE illuminant the scene named for it (null: none, the value is D65-referred RGB); the
  // spectral render emits its spectrum (spectral.hpp, SpectralEmission).
  const color::Illuminant* illuminant() const { return illuminant_; }
  void set_illuminant(const color::Illuminant* i) { illuminant_ = i; }

 private:
  Shape shape_;
  const color::Illuminant* illuminant_ = nullptr;
};
std::ostream& operator<<(std::ostream& os, const Light& l);

// Light arriving from infinity: a constant radiance, or a latitude-longitude map (row 0 = +y;
// u grows with phi = atan2(x, -z) - rotation about +y) importance-sampled by luminance x
// sin(theta). A constant environment is sampled cosine-weighted about the receiver's normal n
// (what a diffuse receiver integrates), a map by its luminance; `pdf` is the same density.
struct Environment {
  Rgb3 constant;                           // radiance of a uniform environment
  std::shared_ptr<const Texture> map;      // lat-long map (multiplies `scale`), optional
  double scale = 1.0;
  double rotation_deg = 0.0;               // about +y
  const color::Illuminant* illuminant = nullptr;  // named in the scene (constant radiance only)
  Distribution2D distribution;             // map importance (luminance x sin theta)
  bool has_map() const { return map != nullptr; }
  bool black() const { return !map && constant.is_black(); }
  Rgb3 radiance(const Vec3& dir) const;
  LightSample sample(const Vec3& p, const Vec3& n, Vec2 u) const;
  double pdf(const Vec3& p, const Vec3& n, const Vec3& wi) const;
  void build_distribution();
};

}  // namespace skin::render
