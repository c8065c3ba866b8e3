// Parameter names, bounds and access; reading and checking measured spectra.
#include <algorithm>
#include <cmath>
#include <ostream>
#include <sstream>

#include "skin/fit/fit.hpp"
#include "skin/util/error.hpp"
#include "skin/util/table.hpp"

namespace skin::fit {

namespace {
struct Entry {
  Parameter p;
  const char* key;
  double SkinParameters::*member;
  Bounds bounds;
};
// Default search intervals. C_m and C_h: the ranges of the paper's figures (DJ06 Figs 3-4, 7:
// C_m up to 50 %, C_h up to 20 %). Epidermal blood: a few percent at most (the papillary
// plexus reaching into the rete ridges; 10 % is generous). Carotene and bilirubin: up to
// 200 umol/L (bilirubin: clinical jaundice is > ~50 umol/L; carotene in skin is far lower, the
// bound only keeps the search finite). Epidermis: 0.02-0.5 mm covers thin eyelid to palm
// (Sandby-Moller et al. 2003 measure 0.03-0.1 mm on most sites; the paper assumes 0.25).
// Scattering: a factor 4 either way around the paper's eq 8.
const Entry kTable[] = {
    {Parameter::melanin, "melanin", &SkinParameters::melanin, {0.0, 0.5}},
    {Parameter::melanin_blend, "melanin_blend", &SkinParameters::melanin_blend, {0.0, 1.0}},
    {Parameter::hemoglobin, "hemoglobin", &SkinParameters::hemoglobin, {0.0, 0.2}},
    {Parameter::oiliness, "oiliness", &SkinParameters::oiliness, {0.0, 1.0}},
    {Parameter::epidermal_hemoglobin, "epidermal_hemoglobin", &SkinParameters::epidermal_hemoglobin,
     {0.0, 0.1}},
    {Parameter::beta_carotene, "beta_carotene", &SkinParameters::beta_carotene, {0.0, 200.0}},
    {Parameter::bilirubin, "bilirubin", &SkinParameters::bilirubin, {0.0, 200.0}},
    {Parameter::epidermis_thickness, "epidermis_thickness", &SkinParameters::epidermis_thickness,
     {0.02, 0.5}},
    {Parameter::oxygenation, "oxygenation", &SkinParameters::oxygenation, {0.0, 1.0}},
    {Parameter::scattering_scale, "scattering_scale", &SkinParameters::scattering_scale,
     {0.25, 4.0}},
};
const Entry& entry(Parameter p) { return kTable[static_cast<int>(p)]; }
}  // namespace

std::string_view key(Parameter p) { return entry(p).key; }
std::string flag(Parameter p) {
  std::string s(entry(p).key);
  std::replace(s.begin(), s.end(), '_', '-');
  return s;
}
std::ostream& operator<<(std::ostream& os, Parameter p) { return os << key(p); }
std::ostream& operator<<(std::ostream& os, const Bounds& b) {
  return os << '[' << b.lo << ", " << b.hi << ']';
}

const std::vector<Parameter>& all_parameters() {
  static const std::vector<Parameter> all = [] {
    std::vector<Parameter> v;
    for (const auto& e : kTable) v.push_back(e.p);
    return v;
  }();
  return all;
}

Parameter parse_parameter(std::string_view name) {
  std::string s(name);
  std::replace(s.begin(), s.end(), '-', '_');
  for (const auto& e : kTable)
    if (s == e.key) return e.p;
  std::string known;
  for (const auto& e : kTable) known += (known.empty() ? "" : ", ") + flag(e.p);
  throw InputError("free parameter '" + std::string(name) + "' is unknown: known are " + known);
}

std::vector<Parameter> parse_parameter_list(std::string_view list) {
  std::vector<Parameter> out;
  std::size_t pos = 0;
  while (pos <= list.size()) {
    const std::size_t comma = std::min(list.find(',', pos), list.size());
    std::string_view item = list.substr(pos, comma - pos);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
    if (item.empty()) throw InputError("free parameter list '" + std::string(list) + "' has an empty entry");
    const Parameter p = parse_parameter(item);
    if (std::find(out.begin(), out.end(), p) != out.end())
      throw InputError("free parameter '" + flag(p) + "' is listed twice");
    out.push_back(p);
    pos = comma + 1;
  }
  return out;
}

double get(const SkinParameters& s, Parameter p) { return s.*(entry(p).member); }
void set(SkinParameters& s, Parameter p, double value) { s.*(entry(p).member) = value; }
Bounds default_bounds(Parameter p) { return entry(p).bounds; }

std::ostream& operator<<(std::ostream& os, const MeasuredSpectrum& m) {
  os << "MeasuredSpectrum{" << m.name << ", " << m.wavelength_nm.size() << " samples";
  if (!m.wavelength_nm.empty()) os << ", " << m.wavelength_nm.front() << "-" << m.wavelength_nm.back() << " nm";
  return os << '}';
}

void validate_spectrum(const MeasuredSpectrum& m) {
  const std::string who = "spectrum '" + m.name + "'";
  if (m.wavelength_nm.size() != m.R.size())
    throw InputError(who + ": " + std::to_string(m.wavelength_nm.size()) + " wavelengths but " +
                     std::to_string(m.R.size()) + " reflectances");
  for (std::size_t i = 0; i < m.R.size(); ++i) {
    const double l = m.wavelength_nm[i], r = m.R[i];
    if (!std::isfinite(l) || l <= 0)
      throw InputError(who + ": wavelength = " + format_number(l) + " nm at sample " +
                       std::to_string(i + 1) + " is not a positive number");
    if (i > 0 && !(l > m.wavelength_nm[i - 1]))
      throw InputError(who + ": wavelengths must increase strictly, but " + format_number(l) +
                       " nm follows " + format_number(m.wavelength_nm[i - 1]) + " nm");
    if (!std::isfinite(r) || r < 0 || r > 1)
      throw InputError(who + ": reflectance = " + format_number(r) + " at " + format_number(l) +
                       " nm is out of range: must be within [0, 1]" +
                       (r > 1 && r <= 100 ? " (a percentage? divide by 100)" : ""));
  }
  if (m.R.empty() || m.wavelength_nm.front() > 450 || m.wavelength_nm.back() < 650)
    throw InputError(who + ": wavelength range " +
                     (m.R.empty() ? std::string("(empty)")
                                  : format_number(m.wavelength_nm.front()) + "-" +
                                        format_number(m.wavelength_nm.back()) + " nm") +
                     " does not cover 450-650 nm");
  const auto n = std::count_if(m.wavelength_nm.begin(), m.wavelength_nm.end(),
                               [](double l) { return l >= 400 && l <= 700; });
  if (static_cast<std::size_t>(n) < kMinSamples)
    throw InputError(who + ": " + std::to_string(n) + " samples within 400-700 nm, at least " +
                     std::to_string(kMinSamples) + " are needed");
}

namespace {
MeasuredSpectrum column_of(const Table& t, std::size_t c, const std::string& name) {
  MeasuredSpectrum m;
  m.name = name;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const double l = t.data[0][i], r = t.data[c][i];
    if (std::isnan(r)) continue;  // an empty field: no measurement at this wavelength
    m.wavelength_nm.push_back(l);
    m.R.push_back(r);
  }
  return m;
}
}  // namespace

MeasuredSpectrum read_spectrum(const std::string& path, const std::string& column) {
  const Table t = read_csv_file(path);
  std::size_t c = 1;
  if (!column.empty()) {
    c = t.column(column);
    if (c == 0) throw InputError(path + ": column '" + column + "' is the wavelength column");
  } else if (t.columns.size() != 2) {
    std::string names;
    for (std::size_t i = 1; i < t.columns.size(); ++i) names += (i > 1 ? ", " : "") + t.columns[i];
    throw InputError(path + ": expected 2 columns (wavelength in nm, reflectance 0-1), found " +
                     std::to_string(t.columns.size()) +
                     (t.columns.size() > 2 ? "; choose one with --column (" + names + ")" : ""));
  }
  MeasuredSpectrum m = column_of(t, c, column.empty() ? path : path + ":" + column);
  validate_spectrum(m);
  return m;
}

std::vector<MeasuredSpectrum> read_spectra(const std::string& path) {
  const Table t = read_csv_file(path);
  if (t.columns.size() < 2)
    throw InputError(path + ": expected a wavelength column and at least one reflectance column");
  std::vector<MeasuredSpectrum> out;
  for (std::size_t c = 1; c < t.columns.size(); ++c) {
    out.push_back(column_of(t, c, t.columns[c]));
    validate_spectrum(out.back());
  }
  return out;
}

}  // namespace skin::fit
