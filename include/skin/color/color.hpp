#pragma once
// Colour from spectra: CIE 1931 2-degree observer (data/cie1931_2deg_xyz.csv) under an
// illuminant (skin/color/illuminant.hpp; D65 by default), linear sRGB (IEC 61966-2-1 matrix),
// white-balanced so that a perfect diffuse reflector is (1, 1, 1) on whatever wavelength grid is
// used; the sRGB transfer curve for 8 bits. Under another illuminant than D65, sRGB is reached
// through the Bradford chromatic adaptation to D65 (docs/illuminants.md).
#include <array>
#include <iosfwd>
#include <string>
#include <vector>

#include "skin/color/illuminant.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/util/rgb.hpp"

namespace skin::color {

struct Xyz {
  double X = 0, Y = 0, Z = 0;
};
using Rgb = skin::util::Rgb;  // linear sRGB unless a name says otherwise
struct Lab {
  double L = 0, a = 0, b = 0;
};
std::ostream& operator<<(std::ostream& os, const Xyz& c);
std::ostream& operator<<(std::ostream& os, const Lab& c);

// The Bradford chromatic adaptation transform (K. M. Lam 1985; the linearised form of CIE 159 and
// ICC.1 v4, Annex E): the XYZ seen under white `from` to the corresponding colour under white
// `to`, a von Kries scaling in the Bradford cone space: M^-1 diag(M to / M from) M. It maps `from`
// to `to` (to rounding). The default is the identity.
class ChromaticAdaptation {
 public:
  ChromaticAdaptation() = default;
  ChromaticAdaptation(const Xyz& from, const Xyz& to);
  Xyz operator()(const Xyz& c) const;
  Xyz inverse(const Xyz& c) const;  // from `to` back to `from`
  bool is_identity() const { return identity_; }

 private:
  using Matrix = std::array<std::array<double, 3>, 3>;
  Matrix forward_{}, backward_{};
  bool identity_ = true;
};

// Colour-matching weights for one wavelength grid under one illuminant. Sums over the grid's
// samples (equal weights: the normalisation by the white cancels the step), so XYZ of a perfect
// reflector has Y = 1.
class Colorimetry {
 public:
  explicit Colorimetry(const physics::WavelengthGrid& grid,
                       const Illuminant& illuminant = find_illuminant(kDefaultIlluminant));
  const physics::WavelengthGrid& grid() const { return grid_; }
  const Illuminant& illuminant() const { return *illuminant_; }
  // XYZ under the illuminant (not adapted). Throws InputError if the spectrum is on another grid.
  Xyz xyz(const physics::Spectrum& reflectance) const;
  // Linear sRGB after the adaptation to D65 (none under D65), white-balanced: a perfect reflector
  // is (1, 1, 1) under every illuminant.
  Rgb srgb_linear(const physics::Spectrum& reflectance) const;
  // The same for an XYZ under the illuminant: adapted, linear sRGB, white-balanced.
  Rgb srgb_linear(const Xyz& c) const;
  Xyz white() const { return white_; }          // the illuminant's white on this grid, Y = 1
  Xyz d65_white() const { return d65_white_; }  // D65's white on this grid, Y = 1
  // The illuminant's white to D65's (Bradford; the identity under D65).
  const ChromaticAdaptation& adaptation() const { return adaptation_; }
  // The illuminant's own colour as a light in white-balanced linear sRGB (no adaptation: how an
  // RGB renderer whose white is D65 sees this light), luminance Y = 1; D65 gives (1, 1, 1).
  Rgb illuminant_rgb() const;
  // Per-wavelength weights w such that srgb_linear = sum_i w[i] R(lambda_i): the colour
  // conversion is linear, so it also applies to profiles in the frequency domain.
  const physics::ChannelWeights& srgb_weights() const { return weights_; }

 private:
  physics::WavelengthGrid grid_;
  const Illuminant* illuminant_;
  std::vector<std::array<double, 3>> xyz_weights_;
  physics::ChannelWeights weights_;
  Xyz white_, d65_white_;
  ChromaticAdaptation adaptation_;
  Rgb white_rgb_;  // D65's white in linear sRGB: the white balance
};

// The CIE 1931 2-degree colour-matching functions xbar, ybar, zbar at lambda [nm]
// (data/cie1931_2deg_xyz.csv, 1 nm steps, linearly interpolated; 0 outside 360-830 nm).
Xyz color_matching(double lambda_nm);

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
// Three signed components whose squares add up to delta_e_2000(a, b)^2 (its lightness, chroma and
// hue differences, the rotation term folded into the last two): residuals for a least-squares fit
// of CIEDE2000.
std::array<double, 3> delta_e_2000_components(const Lab& a, const Lab& b);

// The colour block the command line prints for a reflectance spectrum.
struct ColorSummary {
  std::string illuminant{kDefaultIlluminant};
  Xyz XYZ;  // under the illuminant
  Rgb srgb_linear;
  std::array<int, 3> srgb8{};
  std::string hex;
  Lab lab;  // relative to the illuminant's white on the grid
};
ColorSummary summarize(const Colorimetry& cm, const physics::Spectrum& reflectance);
// From a white-balanced linear sRGB colour (D65-referred): XYZ under cm's illuminant is the
// adaptation undone, CIELAB relative to that illuminant's white.
ColorSummary summarize_rgb(const Colorimetry& cm, const Rgb& srgb_linear);
// From an XYZ under cm's illuminant.
ColorSummary summarize_xyz(const Colorimetry& cm, const Xyz& c);

// How far RGB rendering is from spectral rendering for a uniformly lit half-space under one
// illuminant: the RGB renderer multiplies the skin's RGB albedo (its colour under D65, the
// white-balanced linear sRGB of `R_d`) by the light's RGB (Colorimetry::illuminant_rgb); the
// spectral colour integrates R_d times the illuminant's spectrum. Both XYZ under the illuminant,
// CIELAB relative to its white, compared with CIEDE2000.
struct RgbVsSpectral {
  Rgb rgb_rendering;  // the RGB renderer's pixel: white-balanced linear sRGB, not adapted
  // Both colours as `skin color --illuminant` gives them (XYZ under the illuminant; sRGB and hex
  // after the adaptation to D65; CIELAB relative to the illuminant's white).
  ColorSummary spectral, rgb;
  double delta_e_2000 = 0;  // between spectral.lab and rgb.lab
};
RgbVsSpectral rgb_vs_spectral(const Colorimetry& d65, const Colorimetry& under, const physics::Spectrum& R_d);
std::ostream& operator<<(std::ostream& os, const ColorSummary& c);

}  // namespace skin::color
