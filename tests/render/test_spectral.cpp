// Spectral rendering's pieces (src/render/spectral.hpp): hero wavelengths, RGB -> spectrum
// upsampling and the film, light emission spectra. The renders themselves are checked in
// test_known_answer.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "skin/color/color.hpp"
#include "skin/color/illuminant.hpp"
#include "spectral.hpp"

namespace skin::render {

using skin::physics::WavelengthGrid;

namespace {

// The film's colour of a spectrum (radiance at lambda), integrated over 400-700 nm by the hero
// sampler itself at 75 stratified hero values (300 wavelengths, the midpoints of 1 nm steps).
Rgb3 film_of(const std::function<double(double)>& L) {
  Rgb3 sum;
  constexpr int kHeroes = 75;
  for (int k = 0; k < kHeroes; ++k) {
    const SampledWavelengths wl = SampledWavelengths::hero((k + 0.5) / (kHeroes * kWavelengths));
    SampledSpectrum v;
    for (int j = 0; j < kWavelengths; ++j) v[j] = L(wl.lambda[static_cast<std::size_t>(j)]);
    sum += film_srgb_linear(v, wl);
  }
  return sum / kHeroes;
}

TEST(Spectral, HeroWavelengthsAreRotatedByAQuarterOfTheRange) {
  const SampledWavelengths wl = SampledWavelengths::hero(0.9);
  EXPECT_DOUBLE_EQ(wl.lambda[0], 670.0);
  EXPECT_NEAR(wl.lambda[1], 445.0, 1e-9);  // wrapped
  EXPECT_NEAR(wl.lambda[2], 520.0, 1e-9);
  EXPECT_NEAR(wl.lambda[3], 595.0, 1e-9);
  EXPECT_DOUBLE_EQ(SampledWavelengths::pdf(), 1.0 / 300.0);
  // The 300 midpoints of the hero strata cover 400-700 nm once each.
  std::vector<int> seen(300, 0);
  for (int k = 0; k < 75; ++k)
    for (double l : SampledWavelengths::hero((k + 0.5) / 300).lambda) ++seen[static_cast<std::size_t>(l - 400)];
  for (int s : seen) EXPECT_EQ(s, 1);
}

TEST(Spectral, UpsampledRgbUnderD65RoundTrips) {
  // An RGB reflectance upsampled and lit by D65 (an RGB light of 1, 1, 1) comes back as that RGB
  // on the film: the basis spectra are fitted to it. The film's quadrature here (midpoints of
  // 1 nm steps against the fit's Simpson rule) leaves about 1e-5.
  const RgbUpsampling& up = RgbUpsampling::get();
  const SpectralEmission d65(nullptr);
  double worst = 0;
  for (double r : {0.0, 0.2, 0.55, 1.0})
    for (double g : {0.0, 0.3, 0.7, 1.0})
      for (double b : {0.0, 0.1, 0.6, 1.0}) {
        const Rgb3 rgb{r, g, b};
        const Rgb3 c = film_of([&](double l) { return up(rgb, l) * d65.spd(l); });
        for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(c[i] - rgb[i]));
      }
  EXPECT_LT(worst, 1e-4);
  // The basis is smooth and nearly a reflectance: within [-0.1, 1.1] (reported in
  // docs/renderer.md), white is exactly 1.
  for (int k = 0; k < 6; ++k)
    for (double v : up.basis(k)) {
      EXPECT_GT(v, -0.1) << k;
      EXPECT_LT(v, 1.1) << k;
    }
  EXPECT_EQ(up({0.4, 0.4, 0.4}, 555.5), 0.4);
}

TEST(Spectral, LightsHaveTheColourAndLuminanceOfTheRgbRender) {
  // A white light naming an illuminant emits its spectrum at luminance 1 x the value: on the
  // film, the colour the RGB render gives it (Colorimetry::illuminant_rgb, there summed on the
  // 2 nm grid, here integrated: 2e-3 for smooth spectra; the lines of the fluorescent FL11,
  // tabulated every 5 nm, are sampled differently by the two quadratures: 1.5e-2).
  for (const auto& [name, tolerance] : {std::pair{"D65", 2e-3}, {"A", 2e-3}, {"LED-B3", 2e-3}, {"FL11", 1.5e-2}}) {
    SCOPED_TRACE(name);
    const color::Illuminant& ill = color::find_illuminant(name);
    const Rgb3 expected = color::Colorimetry(WavelengthGrid(), ill).illuminant_rgb();
    const SpectralEmission e(&ill);
    for (const Rgb3 value : {Rgb3{1, 1, 1}, Rgb3{3, 3, 3}}) {
      const Rgb3 L = value * expected;  // what the RGB render's light holds
      Rgb3 c;
      constexpr int kHeroes = 75;
      for (int k = 0; k < kHeroes; ++k) {
        const SampledWavelengths wl = SampledWavelengths::hero((k + 0.5) / (kHeroes * kWavelengths));
        c += film_srgb_linear(e(L, wl), wl) / kHeroes;
      }
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i], L[i], tolerance * std::max(1.0, L[i])) << c << " vs " << L;
    }
  }
}

}  // namespace
}  // namespace skin::render
