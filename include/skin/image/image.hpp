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
  util::Rgb at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
  void set(int x, int y, const util::Rgb& c) {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    rgb[i] = static_cast<float>(c.r);
    rgb[i + 1] = static_cast<float>(c.g);
    rgb[i + 2] = static_cast<float>(c.b);
  }
  // Mean over a pixel rectangle [x0, x1) x [y0, y1).
  util::Rgb mean(int x0, int y0, int x1, int y1) const;
};
std::ostream& operator<<(std::ostream& os, const Image& img);

// Tone curves of PNG output (docs/renderer.md, "Output"): a linear value v (after the exposure)
// to a display value in [0, 1], which is then sRGB-encoded to 8 bits. One name everywhere (the
// CLI's --tone-map, the scene key "tone_map"):
//   clip    min(max(v, 0), 1), the plain sRGB encoding;
//   filmic  J. Hable's filmic curve ("Filmic Tonemapping Operators", 2010, Uncharted 2):
//           H(x) = (x (A x + C B) + D E) / (x (A x + B) + D F) - E / F with A = 0.15, B = 0.50,
//           C = 0.10, D = 0.20, E = 0.02, F = 0.30 and white point W = 11.2, applied to 2 v (his
//           exposure bias) and normalised: min(H(2 v) / H(W), 1). H(0) = 0, it rises
//           monotonically with slope 0.77 at 0 (mid-grey 0.18 -> 0.128, 1 -> 0.493) and reaches 1
//           at v = W / 2 = 5.6, compressing highlights instead of clipping them.
enum class ToneMap { clip, filmic };
// "clip" or "filmic"; anything else: InputError "tone-map = 'x' is not one of clip, filmic".
ToneMap tone_map_from_name(const std::string& name);
const char* tone_map_name(ToneMap t);
double tone_curve(ToneMap t, double v);
// The 8-bit code of a linear value (after the exposure): round(255 srgb_encode(tone_curve(v)));
// non-finite values give 0.
int encode_8bit(ToneMap t, double v);

// Writes by extension: .exr (linear float RGB) or .png (sRGB 8-bit of value x 2^exposure through
// the tone curve). Throws InputError for another extension or a failed write; the target is
// untouched then.
void write_image(const std::string& path, const Image& img, double exposure = 0.0, ToneMap tone_map = ToneMap::clip);

// Reads OpenEXR (by the extension .exr) and Radiance HDR (linear), 8- and 16-bit PNG, JPEG, BMP
// (told by their first bytes) and TGA (by the extension .tga) (grey expanded to RGB, alpha
// dropped; the sRGB transfer curve decoded to linear when `srgb`). Throws InputError naming the
// file when it is missing, unreadable, of another format, or declares more than kMaxImagePixels
// or more pixels than its bytes can hold (checked before anything is decoded).
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
// The same from channels held elsewhere (no copy): each view names a channel and its
// width x height values.
struct PlaneView {
  std::string name;
  const std::vector<float>* values = nullptr;
};
void write_exr_planes(const std::string& path, int width, int height, const std::vector<PlaneView>& planes,
                      const std::vector<std::pair<std::string, std::string>>& attributes,
                      const std::string& what);
// Reads the channels `names` of an OpenEXR file (in that order); throws InputError naming the
// file and the first missing channel.
Planes read_exr_planes(const std::string& path, const std::vector<std::string>& names,
                       const std::string& what);
// The names of an OpenEXR file's channels (in the file's order: alphabetical); InputError if it
// cannot be read.
std::vector<std::string> exr_channel_names(const std::string& path, const std::string& what);

}  // namespace skin::image
