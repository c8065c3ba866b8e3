#pragma once
// Colour from spectra: CIE 1931 2-degree observer under D65 (data/cie1931_2deg_xyz.csv,
// data/d65.csv), linear sRGB (IEC 61966-2-1 matrix), white-balanced so that a perfect diffuse
// reflector is (1, 1, 1) on whatever wavelength grid is used; the sRGB transfer curve for 8 bits.
#include <array>
#include <iosfwd>
#include <string>

#include "skin/transport/profile.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/util/rgb.hpp"

namespace skin::color {

struct Xyz {
  double X = 0, Y = 0, Z = 0;
};
using Rgb = skin::Rgb;  // linear sRGB unless a name says otherwise
struct Lab {
  double L = 0, a = 0, b = 0;
};
std::ostream& operator<<(std::ostream& os, const Xyz& c);
std::ostream& operator<<(std::ostream& os, const Lab& c);

// Colour-matching weights for one wavelength grid. Sums over the grid's samples (equal weights:
// the normalisation by the white cancels the step), so XYZ of a perfect reflector has Y = 1.
class Colorimetry {
 public:
  explicit Colorimetry(const WavelengthGrid& grid);
  const WavelengthGrid& grid() const { return grid_; }
  // Throws InputError if the spectrum is on another grid.
  Xyz xyz(const Spectrum& reflectance) const;
  Rgb srgb_linear(const Spectrum& reflectance) const;
  Xyz white() const { return white_; }
  // Per-wavelength weights w such that srgb_linear = sum_i w[i] R(lambda_i): the colour
  // conversion is linear, so it also applies to profiles in the frequency domain.
  const ChannelWeights& srgb_weights() const { return weights_; }

 private:
  WavelengthGrid grid_;
  std::vector<std::array<double, 3>> xyz_weights_;
  ChannelWeights weights_;
  Xyz white_;
  Rgb white_rgb_;
};

Rgb xyz_to_srgb_linear(const Xyz& c);   // IEC 61966-2-1 matrix (D65 white)
Xyz srgb_linear_to_xyz(const Rgb& c);
double srgb_encode(double linear);      // transfer curve, input clamped to [0, 1]
double srgb_decode(double encoded);
std::array<int, 3> srgb8(const Rgb& linear);  // encoded, rounded, 0-255
std::string hex(const std::array<int, 3>& rgb8);  // "#rrggbb"
// CIELAB relative to a white (Y of the white normalises L*).
Lab xyz_to_lab(const Xyz& c, const Xyz& white);
// CIEDE2000 colour difference (Sharma, Wu & Dalal 2005).
double delta_e_2000(const Lab& a, const Lab& b);

// The colour block the command line prints for a reflectance spectrum.
struct ColorSummary {
  Xyz XYZ;
  Rgb srgb_linear;
  std::array<int, 3> srgb8{};
  std::string hex;
  Lab lab;  // relative to the grid's D65 white
};
ColorSummary summarize(const Colorimetry& cm, const Spectrum& reflectance);
ColorSummary summarize_rgb(const Colorimetry& cm, const Rgb& srgb_linear);
std::ostream& operator<<(std::ostream& os, const ColorSummary& c);

}  // namespace skin::color
