// Fits of measured skin spectra (measured.hpp); the report (docs/validation/measured/) is the
// application's (src/app/report_measured.cpp).
#include "skin/fit/measured.hpp"
#include "skin/fit/color_fit.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <map>
#include <numbers>

#include <tbb/parallel_for.h>

#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"

namespace skin::fit {

using skin::util::InputError;

const std::vector<Parameter>& extended_parameters() {
  static const std::vector<Parameter> v = {
      Parameter::epidermal_hemoglobin, Parameter::beta_carotene, Parameter::bilirubin,
      Parameter::epidermis_thickness,  Parameter::oxygenation,   Parameter::scattering_scale,
      Parameter::blood_vessel_radius};
  return v;
}

double ita_degrees(const color::Lab& lab) {
  return std::atan2(lab.L - 50.0, lab.b) * 180.0 / std::numbers::pi;
}

std::string_view ita_bin(double ita) {
  if (ita > 55) return "very light";
  if (ita > 41) return "light";
  if (ita > 28) return "intermediate";
  if (ita > 10) return "tan";
  if (ita > -30) return "brown";
  return "dark";
}

const std::vector<std::string_view>& ita_bins() {
  static const std::vector<std::string_view> v = {"very light", "light", "intermediate", "tan", "brown", "dark"};
  return v;
}

namespace {

// Text CSV with quoted fields (the metadata files hold labels, which parse_csv does not take).
std::vector<std::vector<std::string>> read_text_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read '" + path + "'");
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f(1);
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) f.emplace_back();
      else f.back() += c;
    }
    rows.push_back(std::move(f));
  }
  return rows;
}

struct Meta {
  std::string description;
  bool paper = false;
  bool includes_specular = false;
};

std::map<std::string, Meta> read_metadata(const std::string& path) {
  const auto rows = read_text_csv(path);
  std::map<std::string, Meta> out;
  if (rows.empty()) return out;
  auto col = [&](const std::string& name) -> int {
    for (std::size_t i = 0; i < rows[0].size(); ++i) {
      std::string h = rows[0][i];
      std::transform(h.begin(), h.end(), h.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      if (h == name) return static_cast<int>(i);
    }
    return -1;
  };
  const int c_name = col("column"), c_label = col("original_label"),
            c_paper = col("used_in_donner_jensen_2006"), c_specular = col("includes_specular");
  if (c_name < 0) return out;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const auto& row = rows[r];
    auto field = [&](int c) { return c >= 0 && static_cast<std::size_t>(c) < row.size() ? row[static_cast<std::size_t>(c)] : std::string(); };
    auto yes = [&](int c) {
      std::string v = field(c);
      std::transform(v.begin(), v.end(), v.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
      return v == "yes";
    };
    out[field(c_name)] = {field(c_label), yes(c_paper), yes(c_specular)};
  }
  return out;
}

}  // namespace

std::vector<MeasuredEntry> fit_measured_spectra(const std::string& spectra_dir, const ForwardModel& model) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(spectra_dir, ec))
    throw InputError("measured spectra: '" + spectra_dir + "' is not a directory");
  std::vector<std::string> files, metas;
  for (const auto& e : fs::recursive_directory_iterator(spectra_dir)) {
    if (!e.is_regular_file() || e.path().extension() != ".csv") continue;
    (e.path().filename().string().find("metadata") != std::string::npos ? metas : files)
        .push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  std::map<std::string, Meta> meta;
  for (const auto& m : metas) meta.merge(read_metadata(m));
  std::vector<MeasuredEntry> entries;
  for (const auto& f : files)
    for (auto& s : read_spectra(f)) {
      MeasuredEntry e;
      e.spectrum = std::move(s);
      if (auto it = meta.find(e.spectrum.name); it != meta.end()) {
        e.description = it->second.description;
        e.used_in_paper = it->second.paper;
        e.includes_specular = it->second.includes_specular;
      }
      entries.push_back(std::move(e));
    }
  if (entries.empty()) throw InputError("measured spectra: no spectra (*.csv) under '" + spectra_dir + "'");

  SpectrumFitOptions paper;
  paper.model = model;
  SpectrumFitOptions spec = paper;
  spec.includes_specular = true;
  SpectrumFitOptions ext = spec;
  for (Parameter p : extended_parameters()) ext.free.push_back(p);
  SpectrumFitOptions prior = paper;
  use_fit_model(prior, FitModel::extended);
  SpectrumFitOptions prior_spec = prior;  // a measurement with the surface reflection in it
  prior_spec.includes_specular = true;
  const SpectrumFitter f_paper(paper), f_spec(spec), f_ext(ext), f_prior(prior), f_prior_spec(prior_spec);
  std::vector<SpectrumFitter> f_single;
  for (Parameter p : extended_parameters()) {
    SpectrumFitOptions o = spec;
    o.free.push_back(p);
    f_single.emplace_back(o);
  }
  tbb::parallel_for(std::size_t(0), entries.size(), [&](std::size_t i) {
    if (util::cancel::requested()) return;  // thrown below
    MeasuredEntry& e = entries[i];
    e.paper = f_paper.fit(e.spectrum);
    e.paper_specular = f_spec.fit(e.spectrum);
    e.extended = f_ext.fit(e.spectrum);
    e.extended_model = (e.includes_specular ? f_prior_spec : f_prior).fit(e.spectrum);
    e.lab = reflectance_lab(e.spectrum.wavelength_nm, e.spectrum.R);
    e.ita = ita_degrees(e.lab);
    for (std::size_t k = 0; k < f_single.size(); ++k)
      e.single_term_rms.emplace_back(extended_parameters()[k], f_single[k].fit(e.spectrum).rms);
  });
  util::cancel::check();
  return entries;
}

}  // namespace skin::fit
