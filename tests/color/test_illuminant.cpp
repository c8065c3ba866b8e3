// The CIE illuminants: their tables against the standard's white points and closed form, the
// Bradford adaptation, and D65 (the default) untouched.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "skin/color/color.hpp"
#include "skin/color/illuminant.hpp"
#include "skin/util/error.hpp"

using namespace skin;
using skin::util::InputError;
using skin::util::Rgb;
using skin::physics::Spectrum;
using skin::physics::TabulatedFunction;
using skin::physics::WavelengthGrid;
using namespace skin::color;

namespace {
double x_of(const Xyz& c) { return c.X / (c.X + c.Y + c.Z); }
double y_of(const Xyz& c) { return c.Y / (c.X + c.Y + c.Z); }
}  // namespace

TEST(Illuminant, NamesAndLookup) {
  const auto names = illuminant_names();
  ASSERT_EQ(names.size(), 15u);
  EXPECT_EQ(names.front(), "D65");
  for (const std::string& n : names) EXPECT_EQ(find_illuminant(n).name(), n);
  EXPECT_EQ(find_illuminant("d65").name(), "D65");
  EXPECT_EQ(find_illuminant("led-b3").name(), "LED-B3");
  // The names before CIE 015:2018 find their successors; other F numbers are not here.
  EXPECT_EQ(find_illuminant("F2").name(), "FL2");
  EXPECT_EQ(find_illuminant("f11").name(), "FL11");
  try {
    (void)find_illuminant("F3");
    FAIL() << "F3 (not tabulated) was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "illuminant = 'F3' is unknown: must be one of D65, D50, A, FL2, FL7, FL11, LED-B1, "
              "LED-B2, LED-B3, LED-B4, LED-B5, LED-BH1, LED-RGB1, LED-V1, LED-V2 (F2, F7, F11 name FL2, "
              "FL7, FL11)");
  }
}

TEST(Illuminant, WhitePointsAreThePublishedOnes) {
  // CIE 015:2018 chromaticities (CIE 1931 2-degree) of the illuminants, computed by the CIE from
  // the 5 nm tables over 380-780 nm: A and the D series to 5 decimals, FL and LED to 4 (here as
  // tabulated in colour-science's chromaticity_coordinates.py, which copies the standard).
  // Tolerance 1e-4: the published rounding (5e-5) plus the data's own (measured: at most 5e-5).
  struct Published {
    const char* name;
    double x, y;
  };
  const Published published[] = {
      {"D65", 0.31272, 0.32903}, {"D50", 0.34567, 0.35851}, {"A", 0.44758, 0.40745},
      {"FL2", 0.3721, 0.3751},   {"FL7", 0.3129, 0.3292},   {"FL11", 0.3805, 0.3769},
      {"LED-B1", 0.4560, 0.4078}, {"LED-B2", 0.4357, 0.4012}, {"LED-B3", 0.3756, 0.3723},
      {"LED-B4", 0.3422, 0.3502}, {"LED-B5", 0.3118, 0.3236}, {"LED-BH1", 0.4474, 0.4066},
      {"LED-RGB1", 0.4557, 0.4211}, {"LED-V1", 0.4548, 0.4044}, {"LED-V2", 0.3781, 0.3775}};
  const WavelengthGrid cie(380, 780, 5);
  for (const Published& p : published) {
    const Colorimetry cm(cie, find_illuminant(p.name));
    EXPECT_NEAR(cm.white().Y, 1.0, 1e-12) << p.name;
    EXPECT_NEAR(x_of(cm.white()), p.x, 1e-4) << p.name;
    EXPECT_NEAR(y_of(cm.white()), p.y, 1e-4) << p.name;
  }
}

TEST(Illuminant, AIsPlancksLawAsTheStandardWritesIt) {
  // ISO/CIE 11664-2 eq. 1: S_A = 100 (560/l)^5 (e^(c2/(T 560)) - 1) / (e^(c2/(T l)) - 1) with
  // c2 = 1.435e-2 m K and T = 2848 K (2856 K with c2 = 1.4388e-2 m K). The illuminant is this
  // closed form; the CIE's table (data/cie_illuminants.csv) holds it to 6 significant digits, so
  // relative differences of at most 5e-6 at the table's wavelengths (300-830 nm, 5 nm).
  const Illuminant& a = find_illuminant("A");
  ASSERT_TRUE(a.has_closed_form());
  const double c2 = 1.435e7;  // [nm K]
  auto planck = [c2](double l, double T) {
    return 100.0 * std::pow(560.0 / l, 5) * std::expm1(c2 / (T * 560.0)) / std::expm1(c2 / (T * l));
  };
  const TabulatedFunction& t = a.table();
  ASSERT_EQ(t.x().size(), 107u);
  double worst = 0, worst_2856 = 0;
  for (std::size_t i = 0; i < t.x().size(); ++i) {
    worst = std::max(worst, std::abs(t.y()[i] / a(t.x()[i]) - 1.0));
    worst_2856 = std::max(worst_2856, std::abs(t.y()[i] / planck(t.x()[i], 2856.0) - 1.0));
  }
  EXPECT_LE(worst, 5e-6);
  // 2856 K with the same c2 (a common slip) is 2 % off: the check tells them apart.
  EXPECT_GT(worst_2856, 1e-2);
  EXPECT_DOUBLE_EQ(a(302.5), planck(302.5, 2848.0));  // between the table's wavelengths
  EXPECT_EQ(a(299), 0.0);
  EXPECT_EQ(a(560), 100.0);
}

TEST(Illuminant, TablesAreZeroOutsideTheirRange) {
  EXPECT_EQ(find_illuminant("FL11")(375), 0.0);
  EXPECT_GT(find_illuminant("FL11")(380), 0.0);
  EXPECT_EQ(find_illuminant("LED-B1")(785), 0.0);
  EXPECT_GT(find_illuminant("D50")(830), 0.0);
  EXPECT_EQ(find_illuminant("D50")(560), 100.0);
}

TEST(ChromaticAdaptation, BradfordMatchesThePublishedD65ToD50Matrix) {
  // B. Lindbloom's Bradford matrix from D65 (0.95047, 1, 1.08883) to D50 (0.96422, 1, 0.82521),
  // published to 7 decimals: the columns are the images of the unit vectors.
  const ChromaticAdaptation cat({0.95047, 1.0, 1.08883}, {0.96422, 1.0, 0.82521});
  const double m[3][3] = {{1.0478112, 0.0228866, -0.0501270},
                          {0.0295424, 0.9904844, -0.0170491},
                          {-0.0092345, 0.0150436, 0.7521316}};
  const Xyz e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int j = 0; j < 3; ++j) {
    const Xyz c = cat(e[j]);
    EXPECT_NEAR(c.X, m[0][j], 6e-8);
    EXPECT_NEAR(c.Y, m[1][j], 6e-8);
    EXPECT_NEAR(c.Z, m[2][j], 6e-8);
  }
}

TEST(ChromaticAdaptation, EveryIlluminantsWhiteBecomesD65sWhite) {
  for (const WavelengthGrid& g : {WavelengthGrid(), WavelengthGrid(380, 780, 5)})
    for (const std::string& n : illuminant_names()) {
      const Colorimetry cm(g, find_illuminant(n));
      const Xyz w = cm.adaptation()(cm.white()), d65 = Colorimetry(g).white();
      EXPECT_NEAR(w.X, d65.X, 1e-14) << n;
      EXPECT_NEAR(w.Y, d65.Y, 1e-14) << n;
      EXPECT_NEAR(w.Z, d65.Z, 1e-14) << n;
      // Hence a perfect reflector is white under every illuminant, and the inverse goes back.
      const Rgb c = cm.srgb_linear(Spectrum(g, 1.0));
      EXPECT_NEAR(c.r, 1.0, 1e-12) << n;
      EXPECT_NEAR(c.g, 1.0, 1e-12) << n;
      EXPECT_NEAR(c.b, 1.0, 1e-12) << n;
      const Xyz back = cm.adaptation().inverse(w);
      EXPECT_NEAR(back.X, cm.white().X, 1e-14) << n;
      EXPECT_NEAR(back.Z, cm.white().Z, 1e-14) << n;
    }
}

TEST(Colorimetry, D65IsTheDefaultAndUnadapted) {
  const WavelengthGrid g;
  const Colorimetry a(g), b(g, find_illuminant("D65"));
  EXPECT_TRUE(a.adaptation().is_identity());
  EXPECT_EQ(a.illuminant().name(), "D65");
  for (std::size_t i = 0; i < g.size(); ++i)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(a.srgb_weights()[i][c], b.srgb_weights()[i][c]);
  EXPECT_EQ(a.illuminant_rgb(), (Rgb{1, 1, 1}));
  EXPECT_FALSE(Colorimetry(g, find_illuminant("A")).adaptation().is_identity());
}

TEST(Colorimetry, XyzAndSrgbOfAReflectanceUnderA) {
  // A reddish reflectance: sRGB goes through the adaptation and summarize_rgb undoes it to the
  // same XYZ (to the sRGB matrices' 7 digits); CIELAB is relative to A's white. (XYZ itself is
  // checked independently by check_illuminants.py.)
  const WavelengthGrid g;
  const Colorimetry cm(g, find_illuminant("A"));
  Spectrum R(g);
  for (std::size_t i = 0; i < g.size(); ++i) R[i] = 0.1 + 0.5 * (g[i] - 400.0) / 300.0;
  const ColorSummary s = summarize(cm, R);
  EXPECT_EQ(s.illuminant, "A");
  const Colorimetry d65(g);
  const ColorSummary back = summarize_rgb(cm, s.srgb_linear);
  EXPECT_NEAR(back.XYZ.X, s.XYZ.X, 1e-6);
  EXPECT_NEAR(back.XYZ.Y, s.XYZ.Y, 1e-6);
  EXPECT_NEAR(back.XYZ.Z, s.XYZ.Z, 1e-6);
  const Lab white = xyz_to_lab(cm.white(), cm.white());
  EXPECT_NEAR(white.L, 100.0, 1e-12);
  EXPECT_NEAR(white.a, 0.0, 1e-12);
  // A has far less blue than D65: the same reflectance's Z differs.
  const Xyz x65 = d65.xyz(R);
  EXPECT_GT(std::abs(s.XYZ.Z - x65.Z), 0.05);
}

TEST(RgbVsSpectral, AgreeUnderD65AndForWhiteAndDifferUnderA) {
  const WavelengthGrid g;
  const Colorimetry d65(g), a(g, find_illuminant("A")), fl11(g, find_illuminant("FL11"));
  Spectrum R(g);
  for (std::size_t i = 0; i < g.size(); ++i) R[i] = 0.05 + 0.4 * std::pow((g[i] - 400.0) / 300.0, 2);
  // Under D65 the RGB albedo is the spectral colour by construction (only the sRGB matrices'
  // 7-digit round trip separates them).
  EXPECT_LT(rgb_vs_spectral(d65, d65, R).delta_e_2000, 1e-3);
  // A perfect reflector reflects the light's own colour either way.
  EXPECT_LT(rgb_vs_spectral(d65, a, Spectrum(g, 1.0)).delta_e_2000, 1e-3);
  EXPECT_LT(rgb_vs_spectral(d65, fl11, Spectrum(g, 1.0)).delta_e_2000, 1e-3);
  // A coloured reflectance under a non-D65 light: the product of RGBs is not the spectral colour.
  const RgbVsSpectral c = rgb_vs_spectral(d65, fl11, R);
  EXPECT_GT(c.delta_e_2000, 0.1);
  EXPECT_NEAR(c.delta_e_2000, delta_e_2000(c.spectral.lab, c.rgb.lab), 0.0);
  EXPECT_THROW((void)rgb_vs_spectral(a, a, R), InputError);
}
