#pragma once
// The project's one RGB value type: three doubles with the component-wise arithmetic of radiance,
// throughput and reflectance. What the channels mean is the user's contract; everywhere in the
// project they are linear sRGB primaries (D65 white) unless a name says "encoded".
#include <algorithm>
#include <iosfwd>

namespace skin::util {

struct Rgb {
  double r = 0, g = 0, b = 0;
  constexpr double operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr double& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr Rgb operator+(const Rgb& o) const { return {r + o.r, g + o.g, b + o.b}; }
  constexpr Rgb operator-(const Rgb& o) const { return {r - o.r, g - o.g, b - o.b}; }
  constexpr Rgb operator*(const Rgb& o) const { return {r * o.r, g * o.g, b * o.b}; }
  constexpr Rgb operator*(double s) const { return {r * s, g * s, b * s}; }
  constexpr Rgb operator/(double s) const { return {r / s, g / s, b / s}; }
  constexpr Rgb& operator+=(const Rgb& o) { r += o.r; g += o.g; b += o.b; return *this; }
  constexpr Rgb& operator*=(const Rgb& o) { r *= o.r; g *= o.g; b *= o.b; return *this; }
  constexpr Rgb& operator*=(double s) { r *= s; g *= s; b *= s; return *this; }
  constexpr double max() const { return std::max({r, g, b}); }
  constexpr double average() const { return (r + g + b) / 3.0; }
  constexpr bool is_black() const { return r == 0 && g == 0 && b == 0; }
  bool operator==(const Rgb&) const = default;
};
constexpr Rgb operator*(double s, const Rgb& c) { return c * s; }
// "RGB(r, g, b)".
std::ostream& operator<<(std::ostream& os, const Rgb& c);

}  // namespace skin::util
