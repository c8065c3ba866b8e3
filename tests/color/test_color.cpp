// Colorimetry against published values.
#include <gtest/gtest.h>

#include "skin/color/color.hpp"

using namespace skin;
using skin::util::Rgb;
using skin::physics::Spectrum;
using skin::physics::WavelengthGrid;
using namespace skin::color;

TEST(Color, D65WhitePointOnTheFullCieGrid) {
  // CIE 15: D65 chromaticity x = 0.31272, y = 0.32903 (2-degree observer). On the 1 nm grid
  // 360-830 nm the data files give 0.31273, 0.32902 (data/PROVENANCE section 2.4).
  const Colorimetry cm(WavelengthGrid(360, 830, 1));
  const Xyz w = cm.white();
  EXPECT_NEAR(w.Y, 1.0, 1e-12);
  EXPECT_NEAR(w.X / (w.X + w.Y + w.Z), 0.31273, 2e-5);
  EXPECT_NEAR(w.Y / (w.X + w.Y + w.Z), 0.32902, 2e-5);
  EXPECT_NEAR(w.X, 0.95047, 1e-4);
  EXPECT_NEAR(w.Z, 1.08883, 1e-4);
}

TEST(Color, PerfectReflectorIsWhiteOnAnyGrid) {
  for (const WavelengthGrid& g : {WavelengthGrid(), WavelengthGrid(400, 700, 10), WavelengthGrid(380, 780, 5)}) {
    const Colorimetry cm(g);
    const Rgb c = cm.srgb_linear(Spectrum(g, 1.0));
    EXPECT_NEAR(c.r, 1.0, 1e-12) << g;
    EXPECT_NEAR(c.g, 1.0, 1e-12) << g;
    EXPECT_NEAR(c.b, 1.0, 1e-12) << g;
    const Rgb half = cm.srgb_linear(Spectrum(g, 0.5));
    EXPECT_NEAR(half.g, 0.5, 1e-12);  // linear
    EXPECT_EQ(hex(srgb8(c)), "#ffffff");
  }
}

TEST(Color, SrgbTransferCurve) {
  // IEC 61966-2-1: 0.5 linear encodes to 0.7354; the curve and its inverse round-trip.
  EXPECT_NEAR(srgb_encode(0.5), 0.735357, 1e-6);
  for (double v : {0.0, 0.001, 0.02, 0.2, 0.7, 1.0}) EXPECT_NEAR(srgb_decode(srgb_encode(v)), v, 1e-12);
  EXPECT_EQ(hex({255, 0, 16}), "#ff0010");
}

TEST(Color, Ciede2000MatchesSharmaTestData) {
  // Sharma, Wu & Dalal (2005), Table 1, pairs 1, 2, 3, 7 and 25.
  EXPECT_NEAR(delta_e_2000({50, 2.6772, -79.7751}, {50, 0, -82.7485}), 2.0425, 1e-4);
  EXPECT_NEAR(delta_e_2000({50, 3.1571, -77.2803}, {50, 0, -82.7485}), 2.8615, 1e-4);
  EXPECT_NEAR(delta_e_2000({50, 2.8361, -74.0200}, {50, 0, -82.7485}), 3.4412, 1e-4);
  EXPECT_NEAR(delta_e_2000({50, 0, 0}, {50, -1, 2}), 2.3669, 1e-4);
  EXPECT_NEAR(delta_e_2000({60.2574, -34.0099, 36.2677}, {60.4626, -34.1751, 39.4387}), 1.2644, 1e-4);
  EXPECT_EQ(delta_e_2000({40, 10, 10}, {40, 10, 10}), 0.0);
}

TEST(Color, LabOfWhiteAndGrey) {
  const Colorimetry cm(WavelengthGrid{});
  EXPECT_NEAR(xyz_to_lab(cm.white(), cm.white()).L, 100.0, 1e-9);
  const Lab grey = xyz_to_lab(cm.xyz(Spectrum(cm.grid(), 0.18)), cm.white());
  EXPECT_NEAR(grey.L, 49.496, 1e-3);  // L* of 18 % grey: 116 * 0.18^(1/3) - 16
  EXPECT_NEAR(grey.a, 0.0, 1e-9);
}
