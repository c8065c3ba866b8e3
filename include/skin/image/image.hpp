#pragma once
// Images and image files, one module for the fit, the renderer and the application: the RGB
// image type (linear float, row 0 at the top), PNG/JPEG/HDR/EXR reading and PNG/EXR writing, and
// named float planes in OpenEXR (the fit's parameter maps). Files are written atomically
// (complete or not at all); every failure is an InputError naming the file. The back-ends
// (libpng, stb_image, OpenEXR) stay inside src/image.
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "skin/util/rgb.hpp"

namespace skin::image {

// The most pixels an image file may declare to be read (8192 x 8192; a texture of that size
// takes 0.8 GB as linear floats). Larger ones are refused before anything is allocated.
inline constexpr long long kMaxImagePixels = 8192LL * 8192LL;

// Linear RGB floats (linear sRGB primaries unless the caller says otherwise), row 0 at the top.
struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3
  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0.0f) {}
  Rgb at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
  void set(int x, int y, const Rgb& c) {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    rgb[i] = static_cast<float>(c.r);
    rgb[i + 1] = static_cast<float>(c.g);
    rgb[i + 2] = static_cast<float>(c.b);
  }
  // Mean over a pixel rectangle [x0, x1) x [y0, y1).
  Rgb mean(int x0, int y0, int x1, int y1) const;
};
std::ostream& operator<<(std::ostream& os, const Image& img);

// Writes by extension: .exr (linear float RGB) or .png (sRGB 8-bit, value x 2^exposure).
// Throws InputError for another extension or a failed write; the target is untouched then.
void write_image(const std::string& path, const Image& img, double exposure = 0.0);

// Reads .exr, .hdr (linear) or 8- and 16-bit .png / .jpg / .tga / .bmp (grey expanded to RGB,
// alpha dropped; the sRGB transfer curve decoded to linear when `srgb`). Throws InputError naming
// the file when it is missing, unreadable or declares more than kMaxImagePixels.
Image read_image(const std::string& path, bool srgb = true);

// Named float channels of one size, row 0 at the top (each plane width * height values).
struct Planes {
  int width = 0, height = 0;
  std::vector<std::string> names;
  std::vector<std::vector<float>> values;  // one per name
};
// Writes an OpenEXR file of float channels with string attributes (name, text) in its header.
// `what` names the content in error messages ("parameter maps").
void write_exr_planes(const std::string& path, const Planes& planes,
                      const std::vector<std::pair<std::string, std::string>>& attributes,
                      const std::string& what);
// Reads the channels `names` of an OpenEXR file (in that order); throws InputError naming the
// file and the first missing channel.
Planes read_exr_planes(const std::string& path, const std::vector<std::string>& names,
                       const std::string& what);

}  // namespace skin::image
