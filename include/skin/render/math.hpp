#pragma once
// Small vector and colour types of the renderer (double precision throughout the shading code;
// only the ray tracing kernel works in float). Lengths are in scene units; the scene says how
// many mm one unit is (scene-format.md), so that diffusion profiles [1/mm^2] scale correctly.
#include <algorithm>
#include <array>
#include <cmath>
#include <iosfwd>
#include <numbers>

#include "skin/util/rgb.hpp"

namespace skin::render {

inline constexpr double kPi = std::numbers::pi;

struct Vec3 {
  double x = 0, y = 0, z = 0;
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  bool operator==(const Vec3&) const = default;
};
constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3& v) { return std::sqrt(dot(v, v)); }
inline Vec3 normalize(const Vec3& v) {
  const double l = length(v);
  return l > 0 ? v / l : Vec3{0, 0, 1};
}
std::ostream& operator<<(std::ostream& os, const Vec3& v);

// Orthonormal basis around a unit normal (Duff et al. 2017, "Building an orthonormal basis,
// revisited": branchless and continuous except on one half-plane).
struct Frame {
  Vec3 s, t, n;
  static Frame from_normal(const Vec3& n) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    return {{1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x}, {b, sign + n.y * n.y * a, -n.y}, n};
  }
  Vec3 to_local(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
  Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

// Linear RGB (linear sRGB primaries, D65 white): radiance, throughput, reflectance; the
// project's one RGB type (skin/util/rgb.hpp).
using Rgb3 = skin::util::Rgb;

}  // namespace skin::render
