// Environment lighting (lights.hpp): a constant radiance, or a latitude-longitude map (row 0 =
// +y, the top; u grows with the angle phi = atan2(x, -z) - rotation about +y) importance-sampled
// in proportion to luminance x sin(theta), the Jacobian of the map's parametrisation.
#include <cmath>

#include "lights.hpp"
#include "scene_data.hpp"

namespace skin::render {
namespace {

void to_uv(const Vec3& d, double rotation, double* u, double* v) {
  const double theta = std::acos(std::clamp(d.y, -1.0, 1.0));
  double phi = std::atan2(d.x, -d.z) - rotation;
  phi -= 2 * kPi * std::floor(phi / (2 * kPi));
  *u = std::min(phi / (2 * kPi), std::nextafter(1.0, 0.0));
  *v = std::min(theta / kPi, std::nextafter(1.0, 0.0));
}

Vec3 from_uv(double u, double v, double rotation) {
  const double theta = v * kPi, phi = u * 2 * kPi + rotation;
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

double luminance(const Rgb3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

// Solid-angle density of a map direction from the density in (u, v): dw = 2 pi^2 sin(theta) du dv.
double map_pdf(double pdf_uv, double sin_theta) { return sin_theta > 0 ? pdf_uv / (2 * kPi * kPi * sin_theta) : 0.0; }

}  // namespace

Rgb3 Environment::radiance(const Vec3& dir) const {
  if (!map) return constant;
  double u, v;
  to_uv(dir, rotation_deg * kPi / 180, &u, &v);
  // Nearest texel: the radiance is piecewise constant exactly like the sampling density.
  return map->texel(static_cast<int>(u * map->width), static_cast<int>(v * map->height)) * scale;
}

void Environment::build_distribution() {
  if (!map) return;
  std::vector<double> w(static_cast<std::size_t>(map->width) * map->height);
  for (int y = 0; y < map->height; ++y) {
    const double sin_theta = std::sin(kPi * (y + 0.5) / map->height);
    for (int x = 0; x < map->width; ++x)
      w[static_cast<std::size_t>(y) * map->width + x] = std::max(0.0, luminance(map->texel(x, y))) * sin_theta;
  }
  distribution = Distribution2D(w, static_cast<std::size_t>(map->width), static_cast<std::size_t>(map->height));
}

LightSample Environment::sample(const Vec3&, const Vec3& n, Vec2 u) const {
  LightSample ls;
  if (!map) {
    const Vec3 l = sample_cosine_hemisphere(u);
    ls.wi = Frame::from_normal(n).to_world(l);
    ls.pdf = pdf_cosine_hemisphere(l.z);
    ls.L = constant;
    return ls;
  }
  double pdf_uv = 0;
  const Vec2 p = distribution.sample(u, &pdf_uv);
  ls.wi = from_uv(p.x, p.y, rotation_deg * kPi / 180);
  const double sin_theta = std::sin(p.y * kPi);
  if (pdf_uv <= 0 || sin_theta <= 0) return ls;
  ls.pdf = map_pdf(pdf_uv, sin_theta);
  ls.L = radiance(ls.wi);
  return ls;
}

double Environment::pdf(const Vec3&, const Vec3& n, const Vec3& wi) const {
  if (!map) return pdf_cosine_hemisphere(dot(wi, n));
  double u, v;
  to_uv(wi, rotation_deg * kPi / 180, &u, &v);
  return map_pdf(distribution.pdf({u, v}), std::sin(v * kPi));
}

}  // namespace skin::render
