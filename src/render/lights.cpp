// Point, directional, sphere and quad lights (lights.hpp): each sampler and its pdf share the
// geometry they are computed from. The environment is in environment.cpp.
#include <cmath>
#include <ostream>

#include "lights.hpp"

namespace skin::render {

LightSample PointLight::sample(const Vec3& p, const Vec3&, Vec2) const {
  LightSample ls;
  const Vec3 v = position - p;
  const double d2 = dot(v, v);
  ls.dist = std::sqrt(d2);
  ls.wi = v / ls.dist;
  ls.L = intensity / d2;
  ls.pdf = 1.0;
  ls.delta = true;
  return ls;
}

LightSample DirectionalLight::sample(const Vec3&, const Vec3&, Vec2) const {
  LightSample ls;
  ls.wi = -direction;
  ls.L = irradiance;
  ls.pdf = 1.0;
  ls.delta = true;
  return ls;
}

bool SphereLight::cone(const Vec3& p, Cone* c) const {
  c->to_centre = centre - p;
  c->dist2 = dot(c->to_centre, c->to_centre);
  if (c->dist2 <= radius * radius) return false;
  c->cos_max = std::sqrt(std::max(0.0, 1 - radius * radius / c->dist2));
  return true;
}

LightSample SphereLight::sample(const Vec3& p, const Vec3&, Vec2 u) const {
  LightSample ls;
  Cone c;
  if (!cone(p, &c)) return ls;
  const double dc = std::sqrt(c.dist2);
  const Frame f = Frame::from_normal(c.to_centre / dc);
  ls.wi = f.to_world(sample_uniform_cone(u, c.cos_max));
  // Distance to the near side of the sphere along wi.
  const double b = dot(-c.to_centre, ls.wi), cc = c.dist2 - radius * radius;
  ls.dist = -b - std::sqrt(std::max(0.0, b * b - cc));
  ls.L = radiance;
  ls.pdf = pdf_uniform_cone(c.cos_max);
  return ls;
}

double SphereLight::pdf(const Vec3& p, const Vec3&, const Vec3& wi) const {
  Cone c;
  if (!cone(p, &c)) return 0.0;
  // Inside the cone: cos(wi, axis) >= cos_max, compared without normalising the axis.
  return dot(wi, c.to_centre) >= c.cos_max * std::sqrt(c.dist2) ? pdf_uniform_cone(c.cos_max) : 0.0;
}

bool SphereLight::intersect(const Vec3& o, const Vec3& d, double* t) const {
  const Vec3 oc = o - centre;
  const double b = dot(oc, d), c = dot(oc, oc) - radius * radius;
  const double disc = b * b - c;
  if (disc < 0 || c < 0) return false;  // missed, or inside the light
  *t = -b - std::sqrt(disc);
  return *t > 0;
}

LightSample QuadLight::sample(const Vec3& p, const Vec3&, Vec2 u) const {
  LightSample ls;
  const Vec3 q = corner + edge_u * u.x + edge_v * u.y;
  const Vec3 v = q - p;
  const double d2 = dot(v, v);
  const double dist = std::sqrt(d2);
  const Vec3 wi = v / dist;
  const double c = -dot(normal(), wi);
  if (c <= 0) return ls;  // behind the emitting side
  ls.dist = dist;
  ls.wi = wi;
  ls.L = radiance;
  ls.pdf = solid_angle_pdf(d2, c);
  return ls;
}

double QuadLight::pdf(const Vec3& p, const Vec3&, const Vec3& wi) const {
  double t = 0;
  if (!intersect(p, wi, &t)) return 0.0;
  return solid_angle_pdf(t * t, -dot(normal(), wi));
}

bool QuadLight::intersect(const Vec3& o, const Vec3& d, double* t) const {
  const Vec3 n = cross(edge_u, edge_v);
  const double dn = dot(d, n);
  if (dn >= 0) return false;  // one-sided: emits toward +n
  *t = dot(corner - o, n) / dn;
  const Vec3 q = o + d * *t - corner;
  const double uu = dot(q, edge_u) / dot(edge_u, edge_u), vv = dot(q, edge_v) / dot(edge_v, edge_v);
  if (uu < 0 || uu > 1 || vv < 0 || vv > 1) return false;
  return *t > 0;
}

std::ostream& operator<<(std::ostream& os, const Light& light) {
  struct Print {
    std::ostream& os;
    void operator()(const PointLight& l) const { os << "PointLight{position=" << l.position << ", intensity=" << l.intensity << '}'; }
    void operator()(const DirectionalLight& l) const {
      os << "DirectionalLight{direction=" << l.direction << ", irradiance=" << l.irradiance << '}';
    }
    void operator()(const SphereLight& l) const {
      os << "SphereLight{centre=" << l.centre << ", radius=" << l.radius << ", radiance=" << l.radiance << '}';
    }
    void operator()(const QuadLight& l) const {
      os << "QuadLight{corner=" << l.corner << ", edge_u=" << l.edge_u << ", edge_v=" << l.edge_v << ", radiance=" << l.radiance << '}';
    }
  };
  std::visit(Print{os}, light.shape());
  return os;
}

}  // namespace skin::render
