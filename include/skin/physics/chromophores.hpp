#pragma once
// Absorption and scattering of the skin's constituents, Donner & Jensen 2006 (DJ06) eqs 3-8.
// All coefficients in 1/mm, wavelengths in nm.

namespace skin::physics::chromophores {

// Hemoglobin content of whole blood and its molar mass (OMLC convention, model-notes section 2).
inline constexpr double kBloodHemoglobin_g_per_L = 150.0;
inline constexpr double kHemoglobinMolarMass_g_per_mol = 64500.0;
inline constexpr double kLn10 = 2.302585092994046;

double sigma_a_eumelanin(double lambda);    // eq 3: 6.6e10 lambda^-3.33
double sigma_a_pheomelanin(double lambda);  // eq 4: 2.9e14 lambda^-4.75
double sigma_a_baseline(double lambda);     // eq 5: 0.0244 + 8.53 exp(-(lambda - 154) / 66.2)
// Whole blood, from Prahl's molar extinction table (data/hemoglobin_prahl.csv):
// sigma_a = ln(10) eps 150 / 64500 per cm, / 10 for 1/mm. Valid 250-1000 nm.
double sigma_a_oxyhemoglobin(double lambda);
double sigma_a_deoxyhemoglobin(double lambda);
// Extended model: absorption per umol/L of beta-carotene and of bilirubin (ln(10) eps c, eps from
// PhotochemCAD, data/*.csv), valid 300-700 nm; zero above 700 nm, where both are negligible.
double sigma_a_beta_carotene_per_uM(double lambda);
double sigma_a_bilirubin_per_uM(double lambda);
// eq 8: reduced scattering of the epidermis, 14.74 lambda^-0.22 + 2.2e11 lambda^-4.
double sigma_s_prime_epidermis(double lambda);

}  // namespace skin::physics::chromophores
