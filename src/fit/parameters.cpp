// The fit's parameters (the parameter table's rows with a fit interval): names, bounds and
// access; reading and checking measured spectra.
#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <sstream>

#include "skin/fit/fit.hpp"
#include "skin/util/error.hpp"
#include "skin/util/table.hpp"

namespace skin::fit {

using skin::util::InputError;
using skin::util::Table;
using skin::util::format_number;
using skin::util::read_csv_file;

using skin::physics::ParameterInfo;
using skin::physics::SkinParameters;
using skin::physics::find_parameter;
using skin::physics::parameter_table;

Parameter Parameter::of(const ParameterInfo& row) {
  if (!row.fittable()) {
    std::string known;
    for (Parameter p : all_parameters()) known += (known.empty() ? "" : ", ") + flag(p);
    throw InputError("free parameter '" + row.flag() + "' cannot be fitted: the fit frees " + known);
  }
  return Parameter(row.member);
}

const ParameterInfo& Parameter::info() const {
  for (const ParameterInfo& row : parameter_table())
    if (row.member == member_) return row;
  ::skin::util::assertion_failed("row.member == member_", __FILE__, __LINE__,
                           "a fit parameter without its row in the parameter table");
}

std::string_view key(Parameter p) { return p.info().key; }
std::string flag(Parameter p) { return p.info().flag(); }
std::ostream& operator<<(std::ostream& os, Parameter p) { return os << key(p); }
std::ostream& operator<<(std::ostream& os, const Bounds& b) {
  return os << '[' << b.lo << ", " << b.hi << ']';
}

const std::vector<Parameter>& all_parameters() {
  static const std::vector<Parameter> all = [] {
    std::vector<Parameter> v;
    for (const ParameterInfo& row : parameter_table())
      if (row.fittable()) v.push_back(Parameter::of(row));
    return v;
  }();
  return all;
}

Parameter parse_parameter(std::string_view name) {
  if (const ParameterInfo* row = find_parameter(name)) return Parameter::of(*row);
  std::string known;
  for (Parameter p : all_parameters()) {
    known += (known.empty() ? "" : ", ") + flag(p);
    if (!p.info().symbol.empty()) known += " (" + std::string(p.info().symbol) + ")";
  }
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

double get(const SkinParameters& s, Parameter p) { return s.*(p.member()); }
void set(SkinParameters& s, Parameter p, double value) { s.*(p.member()) = value; }
Bounds default_bounds(Parameter p) { return {p.info().fit_min, p.info().fit_max}; }

std::string_view name(FitModel m) { return m == FitModel::extended ? "extended" : "paper"; }

FitModel parse_fit_model(std::string_view n) {
  if (n == "paper") return FitModel::paper;
  if (n == "extended") return FitModel::extended;
  throw InputError("model = '" + std::string(n) + "' is unknown: choose paper or extended");
}

std::vector<Parameter> extended_model_free(bool spectrum) {
  // (In the parameter table's order, the order the maps' channels are read back in.)
  std::vector<Parameter> v = {Parameter::melanin,     Parameter::melanin_blend,           Parameter::hemoglobin,
                              Parameter::oxygenation, Parameter::epidermis_thickness,     Parameter::dermis_scattering_scale,
                              Parameter::scattering_scale};
  if (spectrum) {
    v.push_back(Parameter::beta_carotene);
    v.push_back(Parameter::epidermal_hemoglobin);
    v.push_back(Parameter::blood_vessel_radius);
  }
  return v;
}

Bounds prior_bounds(Parameter p) {
  const ParameterInfo& row = p.info();
  return row.has_prior_range() ? Bounds{row.prior_min, row.prior_max} : default_bounds(p);
}

bool has_prior_centre(Parameter p) { return p.info().has_prior_range() && !std::isnan(p.info().prior_centre); }

double prior_coordinate(Parameter p, double v) {
  const ParameterInfo& row = p.info();
  if (!has_prior_centre(p)) return std::numeric_limits<double>::quiet_NaN();
  if (row.prior_log) return std::log(v / row.prior_min) / std::log(row.prior_max / row.prior_min);
  return (v - row.prior_min) / (row.prior_max - row.prior_min);
}

void use_fit_model(SpectrumFitOptions& o, FitModel m) {
  o.fit_model = m;
  o.free = m == FitModel::extended
               ? extended_model_free(true)
               : std::vector<Parameter>{Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin};
}

void check_bounds(const std::vector<std::pair<Parameter, Bounds>>& bounds) {
  for (std::size_t i = 0; i < bounds.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (bounds[i].first == bounds[j].first)
        throw InputError("bounds of " + flag(bounds[i].first) + " are given twice");
}

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
