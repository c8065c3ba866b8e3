#include "skin/physics/skin_parameters.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "skin/physics/chromophores.hpp"
#include "skin/util/error.hpp"
#include "skin/util/random.hpp"

namespace skin::physics {

using skin::util::InputError;
using skin::util::format_number;
using skin::util::require_in_range;
using skin::util::require_positive;
using skin::util::splitmix64;


namespace {
constexpr double kInf = kInfinity;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
double geometric_middle(double lo, double hi) { return std::sqrt(lo * hi); }
// Ranges: the physical domain of each quantity (a fraction within [0, 1]; a length or a scale
// above 0), except beta-carotene and bilirubin, bounded at 1000 umol/L (far beyond physiology)
// to catch unit mistakes, and eta, bounded by the media the Fresnel terms are meant for.
// Skin domain (the two numbers after the member, /*domain*/): the range of human skin the models
// are validated over (issue 31: melanin 0-0.5, blood 0-0.3, epidermis 0.02-0.5 mm, dermis
// scattering 0.2-2, scattering scale 0.25-4, g 0.7-0.97, index 1.33-1.55, the extended
// chromophores over their ranges; roughness 0.1-0.6 around the paper's 0.35).
// Fit intervals (the last two numbers of a row; the rows without them are not fitted): C_m and
// C_h, the ranges of the paper's figures (DJ06 Figs 3-4, 7: C_m up to 50 %, C_h up to 20 %).
// Epidermal blood: a few percent at most (the papillary plexus reaching into the rete ridges;
// 10 % is generous). Carotene and bilirubin: up to 200 umol/L (bilirubin: clinical jaundice is
// > ~50 umol/L; carotene in skin is far lower, the bound only keeps the search finite).
// Epidermis: 0.02-0.5 mm covers thin eyelid to palm (Sandby-Moller et al. 2003 measure
// 0.03-0.1 mm on most sites; the paper assumes 0.25). Scattering: a factor 4 either way around
// the paper's eq 8.
// Priors of the extended fit (/*prior*/: measured range, centre, log scale), the ranges the tone
// presets were fitted in (scripts/fit_tone_presets.py; docs/fit.md "Priors" gives each source):
// C_h 0.2-7 % and epidermis up to 0.15 mm as in Jolivot, Benezeth & Marzani 2013 (Int J Biomed
// Imaging 2013:978289, Table 1, ranges taken from the literature; also oxygenation up to 90 %);
// epidermis centre 0.078 mm (geometric middle) between Sandby-Moller et al. 2003's site means of
// the cellular epidermis, 57-82 um (Acta Derm Venereol 83:410); beta_m centre 0.74, the eumelanin
// share Del Bino et al. 2015 measured in epidermis of every pigmentation (Pigment Cell Melanoma
// Res 28:707). No measured source was found for beta_m's lower end 0.3, oxygenation's 0.6 and
// centre 0.75 (the paper's), or the scattering factor 0.5-2 (the presets' choices). The dermis'
// scattering relative to the epidermis' (extended fit since 2026-12-06, the tone presets since
// 2026-12-07): centre 1, the in vivo model of "Absorption and reduced
// scattering coefficients in epidermis and dermis from a Swedish cohort study" (J Biomed Opt
// 28:115001, 2023; 3809 subjects: one sigma_s' for all layers, 3.22 /mm at 475 nm to 1.20 at
// 850 nm); range 0.5 (the paper's) to 2 (the skin domain's top; no measured bound found).
const ParameterInfo kParameters[] = {
    {"melanin", "C_m", "1", 0, 1, false, false,
     "melanin volume fraction of the epidermis", &SkinParameters::melanin, /*domain*/ 0, 0.5, 0.0, 0.5,
     /*prior*/ 0.0005, 0.5, kNaN, true},
    {"melanin_blend", "beta_m", "1", 0, 1, false, false,
     "eumelanin share of the melanin (the rest is pheomelanin)", &SkinParameters::melanin_blend, /*domain*/ 0, 1,
     0.0, 1.0, /*prior*/ 0.3, 1.0, 0.74, false},
    {"hemoglobin", "C_h", "1", 0, 1, false, false, "blood volume fraction of the dermis",
     &SkinParameters::hemoglobin, /*domain*/ 0, 0.3, 0.0, 0.2,
     /*prior*/ 0.002, 0.07, geometric_middle(0.002, 0.07), true},
    {"oiliness", "rho_s", "1", 0, 1, false, false, "scale of the specular (oily) surface lobe",
     &SkinParameters::oiliness, /*domain*/ 0, 1, 0.0, 1.0},
    {"oxygenation", "gamma", "1", 0, 1, false, false, "oxygenated share of the hemoglobin",
     &SkinParameters::oxygenation, /*domain*/ 0, 1, 0.0, 1.0,
     /*prior*/ 0.6, 0.9, 0.75, false},
    {"epidermis_thickness", "", "mm", 0, kInf, true, true, "thickness of the epidermis",
     &SkinParameters::epidermis_thickness, /*domain*/ 0.02, 0.5, 0.02, 0.5,
     /*prior*/ 0.04, 0.15, geometric_middle(0.04, 0.15), true},
    {"dermis_scattering_scale", "", "1", 0, kInf, true, true,
     "dermis sigma_s_prime relative to the epidermis'", &SkinParameters::dermis_scattering_scale, /*domain*/ 0.2, 2,
     0.2, 2.0, /*prior*/ 0.5, 2.0, 1.0, true},
    {"eta", "", "1", 1, 3, false, false, "refractive index of both layers", &SkinParameters::eta, /*domain*/ 1.33, 1.55},
    {"roughness", "", "1", 0, kInf, true, true, "Beckmann RMS slope of the surface",
     &SkinParameters::roughness, /*domain*/ 0.1, 0.6},
    {"g", "", "1", -1, 1, true, true,
     "Henyey-Greenstein anisotropy (transport models; the paper gives sigma_s_prime only)",
     &SkinParameters::g, /*domain*/ 0.7, 0.97},
    {"epidermal_hemoglobin", "", "1", 0, 1, false, false,
     "extended model: blood volume fraction of the epidermis", &SkinParameters::epidermal_hemoglobin,
     // domain: as its fit range (the epidermis has no vessels of its own; this stands for the
     // papillary capillaries next to it); the whole [0, 1] drew sets with melanin + epidermal blood
     // above 1 (29 % of them), which are not skin and which validate() refuses
     /*domain*/ 0, 0.1, 0.0, 0.1},
    {"beta_carotene", "", "umol/L", 0, 1000, false, false,
     "extended model: beta-carotene in the epidermis", &SkinParameters::beta_carotene, /*domain*/ 0, 1000, 0.0, 200.0},
    {"bilirubin", "", "umol/L", 0, 1000, false, false, "extended model: bilirubin in the dermis",
     &SkinParameters::bilirubin, /*domain*/ 0, 1000, 0.0, 200.0},
    {"scattering_scale", "", "1", 1e-6, 10, false, false,
     "extended model: factor on sigma_s_prime of both layers", &SkinParameters::scattering_scale, /*domain*/ 0.25, 4,
     0.25, 4.0, /*prior*/ 0.5, 2.0, 1.0, true},
    // Vessel packaging (extended model, spectrum fits since 2026-12-07; docs/fit.md): fit
    // interval 0-0.05 mm, no prior centre. No measured range of the effective radius was found
    // to cite; the extended fits of the measured light and intermediate spectra choose 0.012-0.05
    // mm (docs/fit.md, some at the top); the skin domain allows 0-0.1 mm. Not drawn by
    // sample_skin_domain (it only lowers the dermis' absorption).
    {"blood_vessel_radius", "", "mm", 0, 1, false, false,
     "extended model: mean radius of the dermis' blood vessels (packaging; 0 = blood spread evenly)",
     &SkinParameters::blood_vessel_radius, /*domain*/ 0, 0.1, 0.0, 0.05,
     /*prior*/ 0.0, 0.05, kNaN, false, /*sampled*/ false},
};

std::string unit_suffix(std::string_view unit) {
  return unit.empty() || unit == "1" ? std::string() : std::string(unit);
}
}  // namespace

std::span<const ParameterInfo> parameter_table() { return kParameters; }

std::string ParameterInfo::flag() const {
  std::string s(key);
  for (char& c : s)
    if (c == '_') c = '-';
  return s;
}

std::string ParameterInfo::label() const {
  return symbol.empty() ? flag() : flag() + " (" + std::string(symbol) + ")";
}

std::string ParameterInfo::range_text() const {
  return std::string(min_open ? "(" : "[") + format_number(min) + ", " + format_number(max) +
         (max_open ? ")" : "]");
}

double ParameterInfo::default_value() const { return SkinParameters{}.*member; }

std::string ParameterInfo::domain_text() const {
  return "[" + format_number(domain_min) + ", " + format_number(domain_max) + "]";
}

std::vector<std::string> outside_skin_domain(const SkinParameters& p) {
  std::vector<std::string> out;
  for (const auto& info : kParameters) {
    const double v = p.*(info.member);
    if (!info.in_domain(v))
    {
      const std::string u = unit_suffix(info.unit);
      out.push_back(info.label() + " = " + format_number(v) + (u.empty() ? "" : " " + u) +
                    " (skin domain " + info.domain_text() + ")");
    }
  }
  return out;
}

std::vector<SkinParameters> sample_skin_domain(std::size_t n, std::uint64_t seed) {
  // SplitMix64 (skin/util/random.hpp): a fixed sequence on every platform, unlike the standard
  // library's distributions.
  std::uint64_t state = seed;
  auto uniform = [&state] { return static_cast<double>(splitmix64(state) >> 11) * 0x1.0p-53; };  // [0, 1)
  std::vector<SkinParameters> out(n);
  for (auto& p : out) {
    for (const auto& info : kParameters) {
      if (!info.sampled) continue;
      const double lo = info.domain_min, hi = info.domain_max;
      const double edge = uniform(), u = uniform();
      double v;
      if (edge < 0.125) {
        v = lo;
      } else if (edge < 0.25) {
        v = hi;
      } else if (lo > 0 && hi > 4 * lo) {
        v = lo * std::pow(hi / lo, u);
      } else {
        v = lo + (hi - lo) * u;
      }
      p.*(info.member) = std::clamp(v, lo, hi);
    }
  }
  return out;
}


bool ParameterInfo::fittable() const { return !std::isnan(fit_min); }
bool ParameterInfo::has_prior_range() const { return !std::isnan(prior_min) && !std::isnan(prior_max); }

bool ParameterInfo::in_range(double v) const {
  if (std::isnan(v)) return false;
  const bool lo_ok = min_open ? v > min : v >= min;
  const bool hi_ok = max_open ? v < max : v <= max;
  return lo_ok && hi_ok;
}

void ParameterInfo::check(double v) const {
  const std::string name = label(), u = unit_suffix(unit);
  if (!min_open && !max_open) {
    require_in_range(name, v, min, max, u);
  } else if (min == 0 && min_open && std::isinf(max)) {
    require_positive(name, v, u);
  } else if (!in_range(v)) {
    throw InputError(name + " = " + format_number(v) + (u.empty() ? "" : " " + u) +
                     " is out of range: allowed range is " + range_text());
  }
}

const ParameterInfo* find_parameter(std::string_view name) {
  std::string s(name);
  for (char& c : s)
    if (c == '-') c = '_';
  for (const auto& p : kParameters)
    if (p.key == s || (!p.symbol.empty() && p.symbol == name)) return &p;
  return nullptr;
}

std::vector<std::string> parameter_channels(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const auto& p : kParameters)
    if (std::find(names.begin(), names.end(), p.key) != names.end()) out.emplace_back(p.key);
  return out;
}

const ParameterInfo& parameter_info(std::string_view name, std::string_view what) {
  if (const ParameterInfo* p = find_parameter(name)) return *p;
  std::string known;
  for (const auto& p : kParameters) known += (known.empty() ? "" : ", ") + std::string(p.key);
  throw InputError(std::string(what) + " '" + std::string(name) +
                   "' is unknown: known parameters are " + known +
                   " (or the paper's symbols C_m, beta_m, C_h, rho_s, gamma)");
}

const ParameterInfo& ParameterNames::add(std::string_view name) {
  const ParameterInfo& info = parameter_info(name, what_);
  for (const auto& [seen, as] : named_)
    if (seen == &info)
      throw InputError(what_ + " '" + std::string(name) + "' repeats parameter " + std::string(info.key) +
                       " (given as '" + as + "' already)");
  named_.emplace_back(&info, std::string(name));
  return info;
}

void SkinParameters::validate() const {
  for (const auto& p : kParameters) p.check(this->*(p.member));
  if (melanin + epidermal_hemoglobin > 1.0)
    throw InputError("melanin + epidermal-hemoglobin = " +
                     format_number(melanin + epidermal_hemoglobin) +
                     " is out of range: volume fractions must add up to at most 1");
}

std::ostream& operator<<(std::ostream& os, const SkinParameters& p) {
  os << "SkinParameters{";
  bool first = true;
  for (const auto& info : kParameters) {
    const double v = p.*(info.member);
    // The paper's four and its fixed choices always; extended terms only when they are set.
    const bool extended = info.help.starts_with("extended");
    if (extended && v == info.default_value()) continue;
    os << (first ? "" : ", ") << info.key << '=' << v << unit_suffix(info.unit);
    first = false;
  }
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

double vessel_packaging(double sigma_a_blood, double radius) {
  const double x = 2.0 * sigma_a_blood * radius;
  // -expm1(-x) / x: no cancellation for small x; exactly 1 at x = 0 (no packaging).
  return x > 0 ? -std::expm1(-x) / x : 1.0;
}

LayerCoefficients dermis_coefficients(const SkinParameters& p, double lambda) {
  using namespace chromophores;
  // eq 7 (+ bilirubin and vessel packaging in the extended model) and sec 3.5's halved
  // scattering (scaled by dermis_scattering_scale).
  const double sigma_a_blood = blood(p, lambda);
  double sigma_a = p.hemoglobin * sigma_a_blood * vessel_packaging(sigma_a_blood, p.blood_vessel_radius) +
                   (1.0 - p.hemoglobin) * sigma_a_baseline(lambda);
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

namespace {
// The tone presets' fitted values: scripts/fit_tone_presets.py (PYTHONPATH=build/python
// /usr/bin/python3 scripts/fit_tone_presets.py) printed these rows, each the extended colour fit
// of its swatch (`skin fit --hex RRGGBB --model extended`: the priors of docs/fit.md), rounded to
// 4 significant digits; docs/tone-presets.md has the result. The rest are the defaults. gap: the
// CIEDE2000 distance (D65) of the preset's colour from the target, the target's distance from the
// model's gamut where > 1.
struct ToneRow {
  const char* name;
  const char* target;
  double gap;
  double melanin, melanin_blend, hemoglobin, oxygenation, epidermis_thickness, dermis_scattering_scale,
      scattering_scale;
};
constexpr ToneRow kMonk[] = {
    {"monk-01", "f6ede4", 2.98, 0.0005, 0.3, 0.002, 0.9, 0.04, 2, 2},
    {"monk-02", "f3e7db", 2.48, 0.00134, 0.3, 0.002669, 0.9, 0.04, 2, 2},
    {"monk-03", "f7ead0", 4.72, 0.00963, 0.3, 0.002, 0.6, 0.04, 2, 2},
    {"monk-04", "eadaba", 3.27, 0.01995, 0.3, 0.002, 0.6, 0.04, 2, 2},
    {"monk-05", "d7bd96", 0.95, 0.0466, 0.3, 0.002, 0.9, 0.04058, 2, 2},
    {"monk-06", "a07e56", 0.01, 0.06996, 0.7548, 0.002934, 0.7433, 0.06988, 1.052, 0.9328},
    {"monk-07", "825c43", 0.01, 0.08429, 0.7844, 0.01568, 0.7475, 0.1017, 0.9316, 1.26},
    {"monk-08", "604134", 0.01, 0.1217, 0.8684, 0.05309, 0.7505, 0.1188, 0.8013, 1.292},
    {"monk-09", "3a312a", 0.97, 0.2729, 1, 0.07, 0.6, 0.15, 0.5, 2},
    {"monk-10", "292420", 2.13, 0.4595, 1, 0.07, 0.6966, 0.15, 0.5, 2},
};
constexpr const char* kPaperSource =
    "Donner & Jensen 2006: the paper's values, tuned by eye under its multipole model";
constexpr const char* kMonkSource =
    "Monk Skin Tone scale (E. Monk 2019-2023; Google, skintone.google): published sRGB swatch; fitted "
    "by the extended model with the accurate solver under D65 (scripts/fit_tone_presets.py)";
}  // namespace

const std::vector<Preset>& presets() {
  auto make = [](double cm, double bm, double ch, double rs) {
    SkinParameters p;
    p.melanin = cm;
    p.melanin_blend = bm;
    p.hemoglobin = ch;
    p.oiliness = rs;
    return p;
  };
  static const std::vector<Preset> list = [&] {
    std::vector<Preset> l = {
        {"caucasian", "Fig. 8 Caucasian: C_m 0.5%, beta_m 0.7, C_h 0.5%, rho_s 0.3",
         make(0.005, 0.7, 0.005, 0.3), kPaperSource, ""},
        {"asian", "Fig. 8 Asian: C_m 15%, beta_m 0, C_h 1%, rho_s 0.3", make(0.15, 0.0, 0.01, 0.3), kPaperSource,
         ""},
        {"african",
         "Fig. 8 African: C_m 50%, beta_m 0.7, C_h 5%, rho_s 0.3; near black under exact transport (L* 7.0)",
         make(0.50, 0.7, 0.05, 0.3), kPaperSource, ""},
        {"pale", "Fig. 10 pale Caucasian: C_m 0.3%, beta_m 0.25, C_h 0.5%, rho_s 0.3",
         make(0.003, 0.25, 0.005, 0.3), kPaperSource, ""},
        {"tanned", "Fig. 10 tanned Caucasian: C_m 2%, beta_m 0.25, C_h 0.1%, rho_s 0.25",
         make(0.02, 0.25, 0.001, 0.25), kPaperSource, ""},
        {"ear", "Fig. 10 ear / several lights: C_m 0.2%, beta_m 0.5, C_h 1%, rho_s 0.25",
         make(0.002, 0.5, 0.01, 0.25), kPaperSource, ""},
    };
    for (std::size_t i = 0; i < std::size(kMonk); ++i) {
      const ToneRow& r = kMonk[i];
      SkinParameters p;
      p.melanin = r.melanin;
      p.melanin_blend = r.melanin_blend;
      p.hemoglobin = r.hemoglobin;
      p.oxygenation = r.oxygenation;
      p.epidermis_thickness = r.epidermis_thickness;
      p.dermis_scattering_scale = r.dermis_scattering_scale;
      p.scattering_scale = r.scattering_scale;
      std::string d = "Monk Skin Tone " + std::to_string(i + 1) + " (#" + r.target + "), fitted";
      d += r.gap <= 1 ? " to " + format_number(r.gap) + " dE2000"
                      : "; outside the model's gamut: the closest colour is " + format_number(r.gap) + " dE2000 away";
      l.push_back({r.name, d, p, kMonkSource, std::string("#") + r.target});
    }
    return l;
  }();
  return list;
}

std::span<const Preset> paper_presets() {
  constexpr std::size_t kPaper = 6;  // caucasian, asian, african, pale, tanned, ear
  return std::span<const Preset>(presets()).first(kPaper);
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

}  // namespace skin::physics
