#pragma once
// Spectral rendering (internal; docs/renderer.md, "Spectral rendering"): hero wavelength sampling
// (Wilkie et al. 2014), the values a path carries at its four wavelengths, RGB -> spectrum
// upsampling of lights, albedos and textures, the film's XYZ -> linear sRGB, and the spectral
// profiles of a skin material. RGB rendering (the paper's method) uses none of this.
//
// Wavelengths span the model's range, 400-700 nm (its chromophore data end there, and `skin
// color` integrates over the same range), sampled uniformly: a hero wavelength and three more
// spaced by a quarter of the range (rotation), so the four are stratified within each sample.
#include <array>
#include <memory>
#include <vector>

#include "skin/physics/skin_parameters.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/render/bssrdf.hpp"
#include "skin/render/math.hpp"
#include "skin/render/profile_sampler.hpp"
#include "skin/transport/model.hpp"

namespace skin::color {
class Illuminant;
}

namespace skin::render {

inline constexpr int kWavelengths = 4;
inline constexpr double kLambdaMin = 400.0, kLambdaMax = 700.0;  // [nm]

// The four wavelengths of one camera sample [nm]; each has the density 1 / (700 - 400) nm.
struct SampledWavelengths {
  std::array<double, kWavelengths> lambda{};
  // Hero lambda_0 = 400 + 300 u, the others rotated by j/4 of the range (wrapping).
  static SampledWavelengths hero(double u);
  static constexpr double pdf() { return 1.0 / (kLambdaMax - kLambdaMin); }  // [1/nm]
};

// Values at the four wavelengths (radiance, throughput, reflectance), with the arithmetic of Rgb3.
struct SampledSpectrum {
  std::array<double, kWavelengths> v{};
  static constexpr SampledSpectrum constant(double c) { return {{c, c, c, c}}; }
  constexpr double operator[](int i) const { return v[static_cast<std::size_t>(i)]; }
  constexpr double& operator[](int i) { return v[static_cast<std::size_t>(i)]; }
  constexpr SampledSpectrum operator+(const SampledSpectrum& o) const {
    return {{v[0] + o.v[0], v[1] + o.v[1], v[2] + o.v[2], v[3] + o.v[3]}};
  }
  constexpr SampledSpectrum operator*(const SampledSpectrum& o) const {
    return {{v[0] * o.v[0], v[1] * o.v[1], v[2] * o.v[2], v[3] * o.v[3]}};
  }
  constexpr SampledSpectrum operator*(double s) const { return {{v[0] * s, v[1] * s, v[2] * s, v[3] * s}}; }
  constexpr SampledSpectrum operator/(double s) const { return {{v[0] / s, v[1] / s, v[2] / s, v[3] / s}}; }
  constexpr SampledSpectrum& operator+=(const SampledSpectrum& o) { return *this = *this + o; }
  constexpr SampledSpectrum& operator*=(const SampledSpectrum& o) { return *this = *this * o; }
  constexpr SampledSpectrum& operator*=(double s) { return *this = *this * s; }
  constexpr double max() const { return std::max({v[0], v[1], v[2], v[3]}); }
  constexpr double average() const { return (v[0] + v[1] + v[2] + v[3]) / 4.0; }
  constexpr bool is_black() const { return v[0] == 0 && v[1] == 0 && v[2] == 0 && v[3] == 0; }
};

// RGB -> spectrum (Smits 1999's construction: white plus one secondary and one primary colour,
// in proportions that reproduce the RGB), with basis spectra of our own: the smoothest spectra on
// a 10 nm grid (piecewise linear; least squares against a box of the colour's band plus the
// squared second differences) whose colour on the film under D65 is exactly the basis colour.
// So an RGB reflectance rendered under D65, and an RGB light, come out as that RGB (to the film's
// quadrature; tested). White is the constant 1.
class RgbUpsampling {
 public:
  static const RgbUpsampling& get();  // built once (a 34 x 34 solve per basis colour)
  // The spectrum of `rgb` at lambda [nm] (linear in rgb for a fixed ordering of its components).
  double operator()(const Rgb3& rgb, double lambda) const;
  SampledSpectrum operator()(const Rgb3& rgb, const SampledWavelengths& wl) const;
  // Basis k = 0..5: cyan, magenta, yellow, red, green, blue on the grid (for tests and docs).
  const std::vector<double>& basis(int k) const { return basis_[static_cast<std::size_t>(k)]; }
  static physics::WavelengthGrid grid() { return physics::WavelengthGrid(kLambdaMin, kLambdaMax, 10.0); }

 private:
  RgbUpsampling();
  std::array<std::vector<double>, 6> basis_;
};

// The film: the colour of one sample's radiance at its four wavelengths, E[L x CMF / pdf] (CIE
// 1931 2-degree observer) in XYZ, then linear sRGB white-balanced as `skin color` does (a
// radiance of the D65 spectrum normalised to luminance 1 is 1, 1, 1). Linear, so converting each
// sample is the same as converting the accumulated XYZ; the image's sums, error estimate and
// adaptive sampling then work as for RGB.
Rgb3 film_srgb_linear(const SampledSpectrum& L, const SampledWavelengths& wl);

// The emission of a light: its RGB value is upsampled and times the spectrum of its illuminant
// (D65 when none is named) normalised to luminance 1 over 400-700 nm, so that the spectral and
// the RGB renders of a light have the same luminance and, on a white reflector, the same colour.
// `illuminant_rgb` is what the RGB render multiplied the value by (1, 1, 1 for none).
class SpectralEmission {
 public:
  explicit SpectralEmission(const color::Illuminant* illuminant);  // null: D65
  // L: the RGB radiance the light's sampler returned (value x illuminant_rgb x geometry).
  SampledSpectrum operator()(const Rgb3& L, const SampledWavelengths& wl) const;
  double spd(double lambda) const;  // the normalised spectrum [1/nm-weighted luminance]

 private:
  std::vector<double> spd_;  // 1 nm steps over 400-700 nm, luminance-normalised
  Rgb3 illuminant_rgb_{1, 1, 1};
  bool white_ = true;
};

}  // namespace skin::render
