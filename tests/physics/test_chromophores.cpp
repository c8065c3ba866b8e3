// Chromophore data and the skin model's layer coefficients.
#include <gtest/gtest.h>

#include <cmath>

#include "skin/model/skin_model.hpp"
#include "skin/physics/chromophores.hpp"
#include "skin/util/error.hpp"

using namespace skin;

TEST(Chromophores, HemoglobinConversionMatchesHandComputedValue) {
  // Prahl's table at 576 nm: eps(HbO2) = 55540 1/(cm M). Whole blood, 150 g/L, 64500 g/mol:
  // 2.303 * 55540 * 150 / 64500 = 297.5 1/cm = 29.75 1/mm for pure blood (the worked example of
  // shared/data/PROVENANCE.md section 1). The code uses ln 10 = 2.302585093 rather than 2.303.
  EXPECT_NEAR(chromophores::sigma_a_oxyhemoglobin(576.0), 2.302585093 * 55540 * 150 / 64500 / 10, 1e-8);
  EXPECT_NEAR(chromophores::sigma_a_oxyhemoglobin(576.0), 29.75, 0.01);
  // Interpolation between table rows (414 nm is a row; 415 is halfway between 414 and 416).
  const double mid = 0.5 * (chromophores::sigma_a_deoxyhemoglobin(414) + chromophores::sigma_a_deoxyhemoglobin(416));
  EXPECT_NEAR(chromophores::sigma_a_deoxyhemoglobin(415), mid, 1e-12);
  // Outside the table: a clear error, not a silent extrapolation.
  EXPECT_THROW(chromophores::sigma_a_oxyhemoglobin(1200), InputError);
}

TEST(Chromophores, PaperFormulas) {
  // eqs 3-5 and 8 at 500 nm, evaluated by hand.
  EXPECT_NEAR(chromophores::sigma_a_eumelanin(500), 6.6e10 * std::pow(500.0, -3.33), 1e-12);
  EXPECT_NEAR(chromophores::sigma_a_eumelanin(500), 67.92, 0.01);
  EXPECT_NEAR(chromophores::sigma_a_pheomelanin(500), 2.9e14 * std::pow(500.0, -4.75), 1e-12);
  EXPECT_NEAR(chromophores::sigma_a_baseline(500), 0.0244 + 8.53 * std::exp(-346 / 66.2), 1e-15);
  EXPECT_NEAR(chromophores::sigma_s_prime_epidermis(500), 14.74 * std::pow(500.0, -0.22) + 3.52, 1e-12);
}

TEST(SkinModel, LayerCoefficientsFollowEquations6And7) {
  SkinParameters p;
  p.melanin = 0.1;
  p.melanin_blend = 0.3;
  p.hemoglobin = 0.02;
  const double l = 550;
  using namespace chromophores;
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
