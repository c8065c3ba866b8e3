#include "skin/physics/chromophores.hpp"

#include <cmath>
#include <string>

#include "skin/physics/spectrum.hpp"
#include "skin/util/table.hpp"

namespace skin::physics::chromophores {

using skin::util::Table;

namespace {
const TabulatedFunction& hb_table(int column) {
  static const TabulatedFunction oxy = [] {
    const Table& t = util::data::embedded_table("hemoglobin_prahl.csv");
    return TabulatedFunction(t.data[0], t.data[t.column("eps_HbO2")], "data/hemoglobin_prahl.csv");
  }();
  static const TabulatedFunction deoxy = [] {
    const Table& t = util::data::embedded_table("hemoglobin_prahl.csv");
    return TabulatedFunction(t.data[0], t.data[t.column("eps_Hb")], "data/hemoglobin_prahl.csv");
  }();
  return column == 0 ? oxy : deoxy;
}
TabulatedFunction eps_table(const char* file) {
  const Table& t = util::data::embedded_table(file);
  return TabulatedFunction(t.data[0], t.data[1], std::string("data/") + file);
}
const TabulatedFunction& carotene_table() {
  static const TabulatedFunction f = eps_table("beta_carotene.csv");
  return f;
}
const TabulatedFunction& bilirubin_table() {
  static const TabulatedFunction f = eps_table("bilirubin.csv");
  return f;
}
// eps [1/(cm M)] of whole blood's hemoglobin -> sigma_a [1/mm].
constexpr double kBloodFactor =
    kLn10 * kBloodHemoglobin_g_per_L / kHemoglobinMolarMass_g_per_mol / 10.0;
// eps [1/(cm M)] at 1 umol/L -> sigma_a [1/mm]: ln(10) eps 1e-6 / 10.
constexpr double kMicroMolarFactor = kLn10 * 1e-6 / 10.0;
double eps_or_zero_above(const TabulatedFunction& f, double lambda) {
  return lambda > f.x_max() ? 0.0 : f(lambda);
}
}  // namespace

double sigma_a_eumelanin(double lambda) { return 6.6e10 * std::pow(lambda, -3.33); }
double sigma_a_pheomelanin(double lambda) { return 2.9e14 * std::pow(lambda, -4.75); }
double sigma_a_baseline(double lambda) { return 0.0244 + 8.53 * std::exp(-(lambda - 154.0) / 66.2); }
double sigma_a_oxyhemoglobin(double lambda) { return kBloodFactor * hb_table(0)(lambda); }
double sigma_a_deoxyhemoglobin(double lambda) { return kBloodFactor * hb_table(1)(lambda); }
double sigma_a_beta_carotene_per_uM(double lambda) {
  return kMicroMolarFactor * eps_or_zero_above(carotene_table(), lambda);
}
double sigma_a_bilirubin_per_uM(double lambda) {
  return kMicroMolarFactor * eps_or_zero_above(bilirubin_table(), lambda);
}
double sigma_s_prime_epidermis(double lambda) {
  return 14.74 * std::pow(lambda, -0.22) + 2.2e11 * std::pow(lambda, -4.0);
}

}  // namespace skin::physics::chromophores
