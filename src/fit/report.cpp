// Measured-spectra report, docs/validation/measured/.
#include "skin/fit/report.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>

#include <tbb/parallel_for.h>

#include "skin/util/error.hpp"
#include "skin/plot/plot.hpp"

namespace skin::fit {

std::string default_spectra_dir() {
  std::error_code ec;
  const auto p = std::filesystem::weakly_canonical(SKIN_FIT_SPECTRA_DIR, ec);
  return ec ? std::string(SKIN_FIT_SPECTRA_DIR) : p.string();
}

const std::vector<Parameter>& extended_parameters() {
  static const std::vector<Parameter> v = {
      Parameter::epidermal_hemoglobin, Parameter::beta_carotene, Parameter::bilirubin,
      Parameter::epidermis_thickness,  Parameter::oxygenation,   Parameter::scattering_scale};
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
            c_paper = col("used_in_donner_jensen_2006");
  if (c_name < 0) return out;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const auto& row = rows[r];
    auto field = [&](int c) { return c >= 0 && static_cast<std::size_t>(c) < row.size() ? row[static_cast<std::size_t>(c)] : std::string(); };
    std::string paper = field(c_paper);
    std::transform(paper.begin(), paper.end(), paper.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    out[field(c_name)] = {field(c_label), paper == "yes"};
  }
  return out;
}

std::string fmt(double v, const char* f = "%.4f") {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string describe(const FitResult& r) {
  std::string s;
  for (std::size_t i = 0; i < r.free.size(); ++i) {
    if (!s.empty()) s += ", ";
    s += std::string(key(r.free[i])) + " " + fmt(get(r.parameters, r.free[i]), "%.4g");
  }
  return s;
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
  const SpectrumFitter f_paper(paper), f_spec(spec), f_ext(ext);
  std::vector<SpectrumFitter> f_single;
  for (Parameter p : extended_parameters()) {
    SpectrumFitOptions o = spec;
    o.free.push_back(p);
    f_single.emplace_back(o);
  }
  tbb::parallel_for(std::size_t(0), entries.size(), [&](std::size_t i) {
    MeasuredEntry& e = entries[i];
    e.paper = f_paper.fit(e.spectrum);
    e.paper_specular = f_spec.fit(e.spectrum);
    e.extended = f_ext.fit(e.spectrum);
    for (std::size_t k = 0; k < f_single.size(); ++k)
      e.single_term_rms.emplace_back(extended_parameters()[k], f_single[k].fit(e.spectrum).rms);
  });
  return entries;
}

std::vector<MeasuredEntry> write_measured_report(const std::string& spectra_dir, const std::string& out_dir,
                                                 std::ostream& md, const ForwardModel& model,
                                                 const std::string& model_name) {
  namespace fs = std::filesystem;
  std::vector<MeasuredEntry> entries = fit_measured_spectra(spectra_dir, model);
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw InputError("cannot create directory '" + out_dir + "': " + ec.message());
  for (const auto& e : entries) {
    plot::Figure f;
    f.title = e.spectrum.name + (e.description.empty() ? "" : " (" + e.description + ")");
    f.x_label = "wavelength [nm]";
    f.y_label = "reflectance";
    f.y_min = 0.0;
    f.width = 640;
    f.height = 400;
    plot::Series meas{"measured", e.paper.wavelength_nm, e.paper.measured, {0.1, 0.1, 0.1}};
    meas.markers = true;
    f.series.push_back(meas);
    f.series.push_back({"C_m, beta_m, C_h: RMS " + fmt(e.paper.rms), e.paper.wavelength_nm, e.paper.fitted, {0.85, 0.35, 0.1}});
    f.series.push_back({"+ rho_s (specular): RMS " + fmt(e.paper_specular.rms), e.paper.wavelength_nm,
                        e.paper_specular.fitted, {0.2, 0.5, 0.85}, true});
    f.series.push_back({"extended: RMS " + fmt(e.extended.rms), e.paper.wavelength_nm, e.extended.fitted, {0.1, 0.6, 0.25}});
    plot::save(f, (fs::path(out_dir) / (e.spectrum.name + ".png")).string());
  }

  md << "# Measured skin spectra against the model\n\n"
     << "Generated by `skin fit --measured-report <dir>` (skin::fit::write_measured_report) from the "
        "spectra under `" << fs::weakly_canonical(spectra_dir).string() << "` (every `*.csv`; metadata from `*metadata*.csv`). "
        "Each spectrum is fitted over 400-700 nm with the " << model_name << " R_d (docs/fit.md):\n\n"
     << "- **paper**: C_m, beta_m, C_h (the paper's model; rho_s does not enter R_d);\n"
     << "- **+rho_s**: the four parameters, rho_s through a constant specular term rho_s F, F = 0.028 "
        "(the measurement including the surface reflection);\n"
     << "- **extended**: +rho_s and the extended terms epidermal blood, beta-carotene, bilirubin, "
        "epidermis thickness, oxygenation and a scale of sigma_s'.\n\n"
     << "RMS in reflectance units over the measured samples in 400-700 nm. Spectra marked * are the "
        "four the paper compares against (Fig. 9: Vrhel 82, 95, 110, 117).\n\n";
  md << "| spectrum | description | RMS paper | RMS +rho_s | RMS extended | paper fit | extended fit |\n"
     << "|---|---|---:|---:|---:|---|---|\n";
  double worst_flagged = 0;
  for (const auto& e : entries) {
    if (e.used_in_paper) worst_flagged = std::max(worst_flagged, e.extended.rms);
    md << "| [" << e.spectrum.name << (e.used_in_paper ? "*" : "") << "](" << e.spectrum.name << ".png) | "
       << e.description << " | " << fmt(e.paper.rms) << " | " << fmt(e.paper_specular.rms) << " | "
       << fmt(e.extended.rms) << " | " << describe(e.paper) << " | " << describe(e.extended) << " |\n";
  }
  md << "\nWorst extended-model RMS over the paper's four spectra: " << fmt(worst_flagged) << ".\n\n";
  // Summary over all spectra: medians and how many reach RMS < 0.02.
  auto summary = [&](const char* name, auto member) {
    std::vector<double> v;
    for (const auto& e : entries) v.push_back((e.*member).rms);
    std::sort(v.begin(), v.end());
    const auto below = std::count_if(v.begin(), v.end(), [](double x) { return x < 0.02; });
    md << "| " << name << " | " << fmt(v[v.size() / 2]) << " | " << fmt(v.back()) << " | " << below << " / "
       << v.size() << " |\n";
  };
  md << "| model | median RMS | worst RMS | RMS < 0.02 |\n|---|---:|---:|---:|\n";
  summary("paper (C_m, beta_m, C_h)", &MeasuredEntry::paper);
  summary("+rho_s (specular)", &MeasuredEntry::paper_specular);
  summary("extended", &MeasuredEntry::extended);
  md << "\nExtended parameters that end on a bound are marked (bound) below; a term pinned at its "
        "bound (bilirubin at 200 umol/L, scattering scale 4, epidermis at the multipole's validity "
        "limit) is the fit borrowing an absorber or scatterer to bend the spectrum, not a "
        "measurement of it. See docs/fit.md for the discussion.\n\n";
  md << "## Which extended term helps (RMS with the four parameters plus one term)\n\n| spectrum | +rho_s";
  for (Parameter p : extended_parameters()) md << " | +" << key(p);
  md << " | all |\n|---|---:";
  for (std::size_t k = 0; k < extended_parameters().size(); ++k) md << "|---:";
  md << "|---:|\n";
  for (const auto& e : entries) {
    md << "| " << e.spectrum.name << (e.used_in_paper ? "*" : "") << " | " << fmt(e.paper_specular.rms);
    for (const auto& [p, rms] : e.single_term_rms) md << " | " << fmt(rms);
    md << " | " << fmt(e.extended.rms) << " |\n";
  }
  md << "\n## Plots of the paper's four spectra\n\n";
  for (const auto& e : entries)
    if (e.used_in_paper) md << "![" << e.spectrum.name << "](" << e.spectrum.name << ".png)\n\n";
  md << "## Extended fits (all parameters, one standard deviation from the Jacobian)\n\n";
  for (const auto& e : entries) {
    md << "- " << e.spectrum.name << ": ";
    for (std::size_t i = 0; i < e.extended.free.size(); ++i)
      md << (i ? ", " : "") << key(e.extended.free[i]) << " " << fmt(get(e.extended.parameters, e.extended.free[i]), "%.4g")
         << (e.extended.at_bound[i] ? " (bound)" : " ± " + fmt(e.extended.uncertainty[i], "%.2g"));
    md << "\n";
  }
  return entries;
}

}  // namespace skin::fit
