#include "skin/physics/skin_parameters.hpp"

#include <ostream>

#include "skin/physics/chromophores.hpp"
#include "skin/util/error.hpp"

namespace skin {

void SkinParameters::validate() const {
  require_in_range("melanin (C_m)", melanin, 0.0, 1.0);
  require_in_range("melanin-blend (beta_m)", melanin_blend, 0.0, 1.0);
  require_in_range("hemoglobin (C_h)", hemoglobin, 0.0, 1.0);
  require_in_range("oiliness (rho_s)", oiliness, 0.0, 1.0);
  require_in_range("oxygenation (gamma)", oxygenation, 0.0, 1.0);
  require_positive("epidermis-thickness", epidermis_thickness, "mm");
  require_positive("dermis-scattering-scale", dermis_scattering_scale);
  require_in_range("eta", eta, 1.0, 3.0);
  require_positive("roughness", roughness);
  if (!(g > -1.0 && g < 1.0))
    throw InputError("g = " + format_number(g) + " is out of range: allowed range is (-1, 1)");
  require_in_range("epidermal-hemoglobin", epidermal_hemoglobin, 0.0, 1.0);
  if (melanin + epidermal_hemoglobin > 1.0)
    throw InputError("melanin + epidermal-hemoglobin = " +
                     format_number(melanin + epidermal_hemoglobin) +
                     " is out of range: volume fractions must add up to at most 1");
  require_in_range("beta-carotene", beta_carotene, 0.0, 1000.0, "umol/L");
  require_in_range("bilirubin", bilirubin, 0.0, 1000.0, "umol/L");
  require_in_range("scattering-scale", scattering_scale, 1e-6, 10.0);
}

std::ostream& operator<<(std::ostream& os, const SkinParameters& p) {
  os << "SkinParameters{C_m=" << p.melanin << ", beta_m=" << p.melanin_blend
     << ", C_h=" << p.hemoglobin << ", rho_s=" << p.oiliness << ", gamma=" << p.oxygenation
     << ", d_epi=" << p.epidermis_thickness << "mm, dermis_scale=" << p.dermis_scattering_scale
     << ", eta=" << p.eta << ", roughness=" << p.roughness << ", g=" << p.g;
  if (p.epidermal_hemoglobin != 0) os << ", C_he=" << p.epidermal_hemoglobin;
  if (p.beta_carotene != 0) os << ", beta_carotene=" << p.beta_carotene << "uM";
  if (p.bilirubin != 0) os << ", bilirubin=" << p.bilirubin << "uM";
  if (p.scattering_scale != 1) os << ", scattering_scale=" << p.scattering_scale;
  return os << '}';
}

namespace {
double blood(const SkinParameters& p, double lambda) {
  using namespace chromophores;
  return p.oxygenation * sigma_a_oxyhemoglobin(lambda) +
         (1.0 - p.oxygenation) * sigma_a_deoxyhemoglobin(lambda);
}
}  // namespace

LayerCoefficients epidermis_coefficients(const SkinParameters& p, double lambda) {
  using namespace chromophores;
  // eq 6, with the extended model's epidermal blood and carotene added (both 0 by default, in
  // which case this is exactly eq 6).
  const double melanin = p.melanin_blend * sigma_a_eumelanin(lambda) +
                         (1.0 - p.melanin_blend) * sigma_a_pheomelanin(lambda);
  double sigma_a = p.melanin * melanin + (1.0 - p.melanin) * sigma_a_baseline(lambda);
  if (p.epidermal_hemoglobin > 0)
    sigma_a += p.epidermal_hemoglobin * (blood(p, lambda) - sigma_a_baseline(lambda));
  if (p.beta_carotene > 0) sigma_a += p.beta_carotene * sigma_a_beta_carotene_per_uM(lambda);
  return {sigma_a, p.scattering_scale * sigma_s_prime_epidermis(lambda)};
}

LayerCoefficients dermis_coefficients(const SkinParameters& p, double lambda) {
  using namespace chromophores;
  // eq 7 (+ bilirubin in the extended model) and sec 3.5's halved scattering.
  double sigma_a = p.hemoglobin * blood(p, lambda) + (1.0 - p.hemoglobin) * sigma_a_baseline(lambda);
  if (p.bilirubin > 0) sigma_a += p.bilirubin * sigma_a_bilirubin_per_uM(lambda);
  return {sigma_a, p.dermis_scattering_scale * p.scattering_scale * sigma_s_prime_epidermis(lambda)};
}

LayerStack skin_layer_stack(const SkinParameters& p, double lambda) {
  const auto e = epidermis_coefficients(p, lambda);
  const auto d = dermis_coefficients(p, lambda);
  LayerStack s;
  s.eta_above = 1.0;
  s.layers.push_back({e.sigma_a, e.sigma_s_prime, p.epidermis_thickness, p.eta, p.g});
  s.layers.push_back({d.sigma_a, d.sigma_s_prime, kInfinity, p.eta, p.g});
  return s;
}

const std::vector<Preset>& presets() {
  auto make = [](double cm, double bm, double ch, double rs) {
    SkinParameters p;
    p.melanin = cm;
    p.melanin_blend = bm;
    p.hemoglobin = ch;
    p.oiliness = rs;
    return p;
  };
  static const std::vector<Preset> list = {
      {"caucasian", "Fig. 8 Caucasian: C_m 0.5%, beta_m 0.7, C_h 0.5%, rho_s 0.3",
       make(0.005, 0.7, 0.005, 0.3)},
      {"asian", "Fig. 8 Asian: C_m 15%, beta_m 0, C_h 1%, rho_s 0.3", make(0.15, 0.0, 0.01, 0.3)},
      {"african", "Fig. 8 African: C_m 50%, beta_m 0.7, C_h 5%, rho_s 0.3",
       make(0.50, 0.7, 0.05, 0.3)},
      {"pale", "Fig. 10 pale Caucasian: C_m 0.3%, beta_m 0.25, C_h 0.5%, rho_s 0.3",
       make(0.003, 0.25, 0.005, 0.3)},
      {"tanned", "Fig. 10 tanned Caucasian: C_m 2%, beta_m 0.25, C_h 0.1%, rho_s 0.25",
       make(0.02, 0.25, 0.001, 0.25)},
      {"ear", "Fig. 10 ear / several lights: C_m 0.2%, beta_m 0.5, C_h 1%, rho_s 0.25",
       make(0.002, 0.5, 0.01, 0.25)},
  };
  return list;
}

const Preset& find_preset(std::string_view name) {
  std::string_view key = name == "several-lights" ? std::string_view("ear") : name;
  for (const auto& p : presets())
    if (p.name == key) return p;
  std::string known;
  for (const auto& p : presets()) known += (known.empty() ? "" : ", ") + p.name;
  throw InputError("preset = '" + std::string(name) + "' is unknown: known presets are " + known +
                   " (and several-lights = ear)");
}

}  // namespace skin
