#pragma once
// Rendered images: linear RGB floats, row 0 at the top; written as OpenEXR (linear float) or
// PNG (sRGB 8 bits after an exposure in stops), always atomically.
#include <iosfwd>
#include <string>
#include <vector>

#include "skin/render/math.hpp"

namespace skin::render {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3, linear sRGB primaries
  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0.0f) {}
  Rgb3 at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
  void set(int x, int y, const Rgb3& c) {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    rgb[i] = static_cast<float>(c.r);
    rgb[i + 1] = static_cast<float>(c.g);
    rgb[i + 2] = static_cast<float>(c.b);
  }
  // Mean over a pixel rectangle [x0, x1) x [y0, y1).
  Rgb3 mean(int x0, int y0, int x1, int y1) const;
};
std::ostream& operator<<(std::ostream& os, const Image& img);

// Writes by extension: .exr (linear float RGB) or .png (sRGB 8-bit, value x 2^exposure).
// Throws InputError for another extension or a failed write; the target is untouched then.
void write_image(const std::string& path, const Image& img, double exposure = 0.0);

// Reads .exr, .hdr (linear) or .png/.jpg (sRGB decoded to linear when `srgb`).
// Throws InputError naming the file when it is missing or unreadable.
Image read_image(const std::string& path, bool srgb = true);

}  // namespace skin::render
