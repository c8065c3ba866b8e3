// Procedural meshes for the built-in scenes.
#include <cmath>

#include "scene_data.hpp"

namespace skin::render {

Mesh make_ellipsoid(const Vec3& c, const Vec3& radii, int n_theta, int n_phi, std::size_t material) {
  Mesh m;
  m.source = "built-in ellipsoid";
  m.material = material;
  for (int i = 0; i <= n_theta; ++i) {
    const double theta = kPi * i / n_theta;
    for (int j = 0; j <= n_phi; ++j) {
      const double phi = 2 * kPi * j / n_phi;
      const Vec3 d{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
      m.position.push_back(c + Vec3{d.x * radii.x, d.y * radii.y, d.z * radii.z});
      // Normal of an ellipsoid: gradient of sum (x_i / a_i)^2.
      m.normal.push_back(normalize({d.x / radii.x, d.y / radii.y, d.z / radii.z}));
      m.uv.push_back({static_cast<double>(j) / n_phi, 1.0 - static_cast<double>(i) / n_theta});
    }
  }
  const auto idx = [&](int i, int j) { return static_cast<std::uint32_t>(i * (n_phi + 1) + j); };
  for (int i = 0; i < n_theta; ++i)
    for (int j = 0; j < n_phi; ++j) {
      if (i > 0) m.triangles.push_back({idx(i, j), idx(i, j + 1), idx(i + 1, j)});
      if (i + 1 < n_theta) m.triangles.push_back({idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j)});
    }
  return m;
}

Mesh make_sphere(const Vec3& c, double radius, int n_theta, int n_phi, std::size_t material) {
  Mesh m = make_ellipsoid(c, {radius, radius, radius}, n_theta, n_phi, material);
  m.source = "built-in sphere";
  return m;
}

Mesh make_quad(const Vec3& corner, const Vec3& eu, const Vec3& ev, std::size_t material) {
  Mesh m;
  m.source = "built-in quad";
  m.material = material;
  m.position = {corner, corner + eu, corner + eu + ev, corner + ev};
  const Vec3 n = normalize(cross(eu, ev));
  m.normal = {n, n, n, n};
  m.uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

}  // namespace skin::render
