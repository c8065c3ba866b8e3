// Chromophore data and the skin model's layer coefficients. The chromophores are checked against
// published numbers (Prahl's tabulation, the extinction coefficients the data files are scaled
// to, Jacques' melanosome fit), not against the implementation's own formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "skin/model/skin_model.hpp"
#include "skin/physics/chromophores.hpp"
#include "skin/util/error.hpp"
#include "skin/util/table.hpp"
#include "skin_test_paths.hpp"

using namespace skin;
using skin::util::InputError;
using skin::util::Table;
using skin::util::read_csv_file;
using skin::model::SkinSpectrum;
using skin::model::color_under;
using skin::model::skin_spectrum;
using skin::physics::LayerStack;
using skin::physics::SkinParameters;
using skin::physics::Spectrum;
using skin::physics::WavelengthGrid;
using skin::physics::dermis_coefficients;
using skin::physics::epidermis_coefficients;
using skin::physics::find_preset;
using skin::physics::skin_layer_stack;

namespace {
// Whole blood's absorption [1/mm] from a molar extinction coefficient [1/(cm M)], by the recipe
// published with Prahl's table (omlc.org/spectra/hemoglobin/summary.html): mu_a = 2.303 eps x
// 150 g/L / 64,500 g/mol [1/cm]. 2.303 is ln 10 rounded up (by 1.8e-4 relative), hence the
// tolerance of 5e-4 below.
double published_blood_mu_a_per_mm(double eps) { return 2.303 * eps * 150.0 / 64500.0 / 10.0; }
}  // namespace

// Rows of Prahl's "Tabulated Molar Extinction Coefficient for Hemoglobin in Water" (OMLC, 1998),
// as printed there and in Homer's GetExtinctions.m (the cross-checks of shared/data/PROVENANCE.md
// section 1): eps(HbO2), eps(Hb) in 1/(cm M).
TEST(Chromophores, HemoglobinMatchesPrahlsPublishedRows) {
  struct Row {
    double lambda, hbo2, hb;
  };
  for (const Row& r : {Row{250, 106112, 112736}, Row{400, 266232, 223296}, Row{414, 524280, 342596}}) {
    EXPECT_NEAR(physics::chromophores::sigma_a_oxyhemoglobin(r.lambda) / published_blood_mu_a_per_mm(r.hbo2), 1.0, 5e-4)
        << r.lambda;
    EXPECT_NEAR(physics::chromophores::sigma_a_deoxyhemoglobin(r.lambda) / published_blood_mu_a_per_mm(r.hb), 1.0, 5e-4)
        << r.lambda;
  }
  EXPECT_NEAR(physics::chromophores::sigma_a_oxyhemoglobin(576) / published_blood_mu_a_per_mm(55540), 1.0, 5e-4);
}

// Every row of the published tabulation as kept in ../shared/data (hemoglobin/
// prahl_extinction.csv, 250-1000 nm every 2 nm; not part of the build), where it is present.
TEST(Chromophores, HemoglobinMatchesPrahlsWholeTable) {
  const std::filesystem::path file = std::filesystem::path(SKIN_SHARED_DATA_DIR) / "hemoglobin" / "prahl_extinction.csv";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is not present";
  const Table t = read_csv_file(file.string());
  ASSERT_EQ(t.rows(), 376u);
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const double lambda = t.data[0][i];
    EXPECT_NEAR(physics::chromophores::sigma_a_oxyhemoglobin(lambda) / published_blood_mu_a_per_mm(t.data[1][i]), 1.0, 5e-4)
        << lambda;
    EXPECT_NEAR(physics::chromophores::sigma_a_deoxyhemoglobin(lambda) / published_blood_mu_a_per_mm(t.data[2][i]), 1.0, 5e-4)
        << lambda;
  }
}

// The extended model's chromophores at the extinction coefficients their spectra are scaled to:
// beta-carotene 139,500 1/(cm M) at 451 nm in hexane (Zechmeister & Polgar 1943), bilirubin
// 55,000 1/(cm M) at 450.8 nm in chloroform (Agati & Fusi 1990). At 1 umol/L: mu_a = ln(10) eps
// 1e-6 [1/cm]. The data files are on a 1 nm grid interpolated from PhotochemCAD's 0.25 nm one:
// within 0.5 % at the peak.
TEST(Chromophores, CaroteneAndBilirubinMatchTheirPublishedPeaks) {
  const double per_uM = std::log(10.0) * 1e-6 / 10.0;
  EXPECT_NEAR(physics::chromophores::sigma_a_beta_carotene_per_uM(451) / (139500 * per_uM), 1.0, 5e-3);
  EXPECT_NEAR(physics::chromophores::sigma_a_bilirubin_per_uM(450.8) / (55000 * per_uM), 1.0, 5e-3);
}

// The paper's eumelanin (DJ06 eq 3) against an independent published fit: Jacques' melanosome
// absorption for skin, mu_a = 1.70e12 lambda^-3.48 [1/cm] (S. L. Jacques, "Melanosome absorption
// coefficient", omlc.org/spectra/melanin/mua.html, 1998). They agree within 5 % over 400-700 nm
// (4.6 % at most, at 400 nm): a unit slip (a factor 10) or a wrong exponent would not.
TEST(Chromophores, EumelaninAgreesWithJacquesMelanosomeFit) {
  for (double l = 400; l <= 700; l += 10) {
    const double jacques = 1.70e12 * std::pow(l, -3.48) / 10.0;
    EXPECT_NEAR(physics::chromophores::sigma_a_eumelanin(l) / jacques, 1.0, 0.05) << l;
  }
}

TEST(Chromophores, HemoglobinConversionMatchesHandComputedValue) {
  // Prahl's table at 576 nm: eps(HbO2) = 55540 1/(cm M). Whole blood, 150 g/L, 64500 g/mol:
  // 2.303 * 55540 * 150 / 64500 = 297.5 1/cm = 29.75 1/mm for pure blood (the worked example of
  // shared/data/PROVENANCE.md section 1). The code uses ln 10 = 2.302585093 rather than 2.303.
  EXPECT_NEAR(physics::chromophores::sigma_a_oxyhemoglobin(576.0), 2.302585093 * 55540 * 150 / 64500 / 10, 1e-8);
  EXPECT_NEAR(physics::chromophores::sigma_a_oxyhemoglobin(576.0), 29.75, 0.01);
  // Interpolation between table rows (414 nm is a row; 415 is halfway between 414 and 416).
  const double mid = 0.5 * (physics::chromophores::sigma_a_deoxyhemoglobin(414) + physics::chromophores::sigma_a_deoxyhemoglobin(416));
  EXPECT_NEAR(physics::chromophores::sigma_a_deoxyhemoglobin(415), mid, 1e-12);
  // Outside the table: a clear error, not a silent extrapolation.
  EXPECT_THROW(physics::chromophores::sigma_a_oxyhemoglobin(1200), InputError);
}

TEST(Chromophores, PaperFormulas) {
  // eqs 3-5 and 8 at 500 nm, evaluated by hand.
  EXPECT_NEAR(physics::chromophores::sigma_a_eumelanin(500), 6.6e10 * std::pow(500.0, -3.33), 1e-12);
  EXPECT_NEAR(physics::chromophores::sigma_a_eumelanin(500), 67.92, 0.01);
  EXPECT_NEAR(physics::chromophores::sigma_a_pheomelanin(500), 2.9e14 * std::pow(500.0, -4.75), 1e-12);
  EXPECT_NEAR(physics::chromophores::sigma_a_baseline(500), 0.0244 + 8.53 * std::exp(-346 / 66.2), 1e-15);
  EXPECT_NEAR(physics::chromophores::sigma_s_prime_epidermis(500), 14.74 * std::pow(500.0, -0.22) + 3.52, 1e-12);
}

TEST(SkinModel, LayerCoefficientsFollowEquations6And7) {
  SkinParameters p;
  p.melanin = 0.1;
  p.melanin_blend = 0.3;
  p.hemoglobin = 0.02;
  const double l = 550;
  using namespace physics::chromophores;
  const auto e = epidermis_coefficients(p, l);
  EXPECT_NEAR(e.sigma_a, 0.1 * (0.3 * sigma_a_eumelanin(l) + 0.7 * sigma_a_pheomelanin(l)) + 0.9 * sigma_a_baseline(l), 1e-12);
  const auto d = dermis_coefficients(p, l);
  EXPECT_NEAR(d.sigma_a, 0.02 * (0.75 * sigma_a_oxyhemoglobin(l) + 0.25 * sigma_a_deoxyhemoglobin(l)) + 0.98 * sigma_a_baseline(l), 1e-12);
  EXPECT_NEAR(d.sigma_s_prime, 0.5 * e.sigma_s_prime, 1e-12);
  const LayerStack s = skin_layer_stack(p, l);
  ASSERT_EQ(s.layers.size(), 2u);
  EXPECT_EQ(s.layers[0].thickness, 0.25);
  EXPECT_TRUE(s.layers[1].semi_infinite());
  EXPECT_EQ(s.layers[0].eta, 1.4);
}

TEST(SkinModel, ExtendedTermsAreOffByDefaultAndRaiseAbsorption) {
  SkinParameters p;
  const auto base = epidermis_coefficients(p, 460);
  p.beta_carotene = 5.0;
  EXPECT_GT(epidermis_coefficients(p, 460).sigma_a, base.sigma_a);
  p = SkinParameters{};
  p.bilirubin = 50.0;
  EXPECT_GT(dermis_coefficients(p, 460).sigma_a, dermis_coefficients(SkinParameters{}, 460).sigma_a);
}

// Vessel packaging: the factor is the mean transmission of blood along a path of length 2R,
// (1 / 2R) int_0^2R exp(-mu s) ds (Svaasand et al. 1995; van Veen et al. 2002), here by a
// midpoint sum of 200 000 steps (relative error below 1e-10 for mu R <= 5), against the closed form;
// with its limits (1 at R = 0, 1 / (2 mu R) far into the blood) and its effect on the dermis:
// only the blood's term shrinks, the Soret band (415 nm, blood's mu ~ 280 /mm) far more than red
// light (650 nm, ~0.65 /mm).
TEST(SkinModel, VesselPackagingIsTheMeanTransmissionAcrossAVessel) {
  using physics::vessel_packaging;
  for (const double mu : {0.02, 1.0, 20.0, 100.0})
    for (const double r : {1e-4, 0.005, 0.02, 0.05}) {
      const int n = 200000;
      const double h = 2 * r / n;
      double sum = 0;
      for (int i = 0; i < n; ++i) sum += std::exp(-mu * (i + 0.5) * h);
      EXPECT_NEAR(vessel_packaging(mu, r), sum * h / (2 * r), 1e-9) << mu << " " << r;
    }
  EXPECT_EQ(vessel_packaging(30.0, 0.0), 1.0);
  EXPECT_EQ(vessel_packaging(0.0, 0.03), 1.0);
  EXPECT_NEAR(vessel_packaging(1e-9, 1e-3), 1.0 - 1e-12, 1e-15);  // 1 - x / 2: no cancellation near 0
  EXPECT_NEAR(vessel_packaging(500.0, 0.05) * 2 * 500.0 * 0.05, 1.0, 1e-12);

  SkinParameters p;
  p.hemoglobin = 0.03;
  using namespace physics::chromophores;
  for (const double l : {415.0, 650.0}) {
    SkinParameters q = p;
    q.blood_vessel_radius = 0.02;
    const double blood = 0.75 * sigma_a_oxyhemoglobin(l) + 0.25 * sigma_a_deoxyhemoglobin(l);
    EXPECT_NEAR(dermis_coefficients(q, l).sigma_a,
                0.03 * blood * vessel_packaging(blood, 0.02) + 0.97 * sigma_a_baseline(l), 1e-12);
    EXPECT_EQ(dermis_coefficients(q, l).sigma_s_prime, dermis_coefficients(p, l).sigma_s_prime);
    EXPECT_EQ(epidermis_coefficients(q, l).sigma_a, epidermis_coefficients(p, l).sigma_a);
  }
  SkinParameters q = p;
  q.blood_vessel_radius = 0.02;
  const auto blood_part = [](const SkinParameters& s, double l) {
    SkinParameters none = s;
    none.hemoglobin = 0;
    return dermis_coefficients(s, l).sigma_a - dermis_coefficients(none, l).sigma_a * (1 - s.hemoglobin);
  };
  EXPECT_LT(blood_part(q, 415) / blood_part(p, 415), 0.1);   // 2 mu R ~ 11: ~0.09
  EXPECT_GT(blood_part(q, 650) / blood_part(p, 650), 0.98);  // 2 mu R ~ 0.026: ~0.987
}

TEST(SkinModel, PresetsOrderByLightness) {
  // Fig. 8 / Fig. 10: pale and Caucasian are lightest, then tanned, Asian, African.
  const WavelengthGrid grid;
  auto L = [&](const char* name) { return skin_spectrum(find_preset(name).parameters, grid).color.lab.L; };
  const double pale = L("pale"), cauc = L("caucasian"), tan = L("tanned"), asian = L("asian"), african = L("african");
  EXPECT_GT(pale, cauc);
  EXPECT_GT(cauc, tan);
  EXPECT_GT(tan, asian);
  EXPECT_GT(asian, african);
  EXPECT_LT(african, 30.0);  // dark skin
  EXPECT_GT(pale, 65.0);     // light skin
}

TEST(SkinModel, MoreMelaninOrBloodNeverBrightens) {
  const WavelengthGrid grid(400, 700, 10);
  SkinParameters p;
  double previous = 2.0;
  for (double cm : {0.001, 0.01, 0.05, 0.2, 0.5}) {
    p.melanin = cm;
    const Spectrum R = skin_spectrum(p, grid).R_d;
    for (std::size_t i = 0; i < grid.size(); ++i) EXPECT_GT(R[i], 0.0);
    const double Y = skin_spectrum(p, grid).color.XYZ.Y;
    EXPECT_LT(Y, previous);
    previous = Y;
  }
}

// color_under: the spectrum's own colour under its own illuminant (D65), the colour of R_d under
// another one, the same with the weights given; weights of another grid are refused.
TEST(SkinModel, ColorUnderAnIlluminant) {
  const WavelengthGrid grid(400, 700, 10);
  const SkinSpectrum s = skin_spectrum(find_preset("tanned").parameters, grid);
  const color::ColorSummary d65 = color_under(s, color::find_illuminant("d65"));
  EXPECT_EQ(d65.illuminant, "D65");
  EXPECT_EQ(d65.hex, s.color.hex);
  EXPECT_EQ(d65.XYZ.Y, s.color.XYZ.Y);
  const color::Illuminant& a = color::find_illuminant("A");
  const color::ColorSummary under_a = color_under(s, a);
  const color::ColorSummary expected = color::summarize(color::Colorimetry(grid, a), s.R_d);
  EXPECT_EQ(under_a.illuminant, "A");
  EXPECT_EQ(under_a.XYZ.X, expected.XYZ.X);
  EXPECT_EQ(under_a.lab.b, expected.lab.b);
  EXPECT_GT(under_a.XYZ.X / under_a.XYZ.Z, 2.0 * d65.XYZ.X / d65.XYZ.Z);  // A is a warm light
  EXPECT_EQ(color_under(s, color::Colorimetry(grid, a)).hex, under_a.hex);
  EXPECT_EQ(color_under(s, color::Colorimetry(grid)).hex, s.color.hex);
  EXPECT_THROW(color_under(s, color::Colorimetry(WavelengthGrid(400, 700, 5), a)), InputError);
}
