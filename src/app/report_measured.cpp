// The measured-spectra report (report_measured.hpp).
#include "report_measured.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <sstream>

#include "skin/fit/color_fit.hpp"
#include "skin/plot/plot.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"

namespace skin::cli {

using skin::util::InputError;

using fit::extended_parameters;
using fit::FitResult;
using fit::get;
using fit::key;
using fit::MeasuredEntry;
using fit::Parameter;

namespace {

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

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The entries whose measured colour falls in a skin-tone bin (fit::ita_bin), in their order.
std::vector<const MeasuredEntry*> in_bin(const std::vector<MeasuredEntry>& entries, std::string_view bin) {
  std::vector<const MeasuredEntry*> in;
  for (const auto& e : entries)
    if (fit::ita_bin(e.ita) == bin) in.push_back(&e);
  return in;
}

// Fits grouped by skin-tone bin (ITA of the measured colour), for the paper's parameters and for
// `--model extended`: count, median and worst RMS, median dE2000, parameters at bounds, spread.
void write_tone_bins(std::ostream& md, const std::vector<MeasuredEntry>& entries) {
  md << "\n## By skin tone (ITA)\n\n"
     << "Each measured spectrum's colour (D65, `skin color`'s grid) gives its Individual Typology "
        "Angle ITA = atan((L* - 50) / b*); bins: very light > 55, light 41-55, intermediate 28-41, "
        "tan 10-28, brown -30-10, dark < -30 degrees. **paper**: C_m, beta_m, C_h; **extended**: "
        "`skin fit --model extended` (docs/fit.md: ten parameters, measured ranges and priors). "
        "At bound: free parameters that ended on a bound, summed over the bin's fits.\n\n"
     << "| bin | n | model | median RMS | worst RMS | median dE2000 | at bound | parameter range (min-max) |\n"
     << "|---|---:|---|---:|---:|---:|---:|---|\n";
  struct BinStat {
    std::string bin;
    double median_rms[2];
  };
  std::vector<BinStat> stats;
  for (std::string_view bin : fit::ita_bins()) {
    const std::vector<const MeasuredEntry*> in = in_bin(entries, bin);
    if (in.empty()) {
      md << "| " << bin << " | 0 | | | | | | |\n";
      continue;
    }
    BinStat st{std::string(bin), {0, 0}};
    for (int model = 0; model < 2; ++model) {
      std::vector<double> rms, de;
      std::size_t bound = 0;
      const FitResult& first = model ? in.front()->extended_model : in.front()->paper;
      std::string spread;
      for (std::size_t k = 0; k < first.free.size(); ++k) {
        double lo = 1e300, hi = -1e300;
        for (const MeasuredEntry* e : in) {
          const double v = get((model ? e->extended_model : e->paper).parameters, first.free[k]);
          lo = std::min(lo, v), hi = std::max(hi, v);
        }
        spread += (k ? ", " : "") + std::string(key(first.free[k])) + " " + fmt(lo, "%.3g") + "-" + fmt(hi, "%.3g");
      }
      for (const MeasuredEntry* e : in) {
        const FitResult& r = model ? e->extended_model : e->paper;
        rms.push_back(r.rms);
        de.push_back(r.delta_e);
        bound += static_cast<std::size_t>(std::count(r.at_bound.begin(), r.at_bound.end(), true));
      }
      st.median_rms[model] = median(rms);
      md << "| " << (model ? "" : std::string(bin)) << " | " << (model ? "" : std::to_string(in.size())) << " | "
         << (model ? "extended" : "paper") << " | " << fmt(median(rms)) << " | "
         << fmt(*std::max_element(rms.begin(), rms.end())) << " | " << fmt(median(de), "%.2f") << " | " << bound
         << " | " << spread << " |\n";
    }
    stats.push_back(st);
  }
  md << "\nSpectra per bin:";
  for (std::string_view bin : fit::ita_bins()) {
    std::string names;
    for (const auto& e : entries)
      if (fit::ita_bin(e.ita) == bin) names += (names.empty() ? "" : ", ") + e.spectrum.name + " (" + fmt(e.ita, "%.0f") + ")";
    if (!names.empty()) md << "\n- " << bin << ": " << names;
  }
  md << "\n\nChecks (issue 32), as measured:\n\n";
  for (int model = 0; model < 2; ++model) {
    double best = 1e300, worst = 0;
    std::string best_bin, worst_bin;
    bool all_below = true;
    for (const auto& st : stats) {
      if (st.median_rms[model] < best) best = st.median_rms[model], best_bin = st.bin;
      if (st.median_rms[model] > worst) worst = st.median_rms[model], worst_bin = st.bin;
      all_below = all_below && st.median_rms[model] <= 0.005;
    }
    md << "- " << (model ? "extended" : "paper") << ": worst bin's median RMS " << fmt(worst) << " (" << worst_bin
       << ") is " << fmt(worst / best, "%.2f") << "x the best's " << fmt(best) << " (" << best_bin << "): "
       << (worst <= 1.5 * best ? "within" : "NOT within") << " 1.5x; median RMS <= 0.005 in every bin: "
       << (all_below ? "yes" : "no") << ".\n";
  }
  // The extended model's bounds are the measured ranges, so every fit lies inside them; what tells
  // is how many fits lean on an end of one (a parameter with a measured range on its bound).
  std::size_t clear = 0;
  for (const auto& e : entries) {
    const FitResult& r = e.extended_model;
    bool leans = false;
    for (std::size_t k = 0; k < r.free.size() && k < r.at_bound.size(); ++k)
      leans = leans || (r.at_bound[k] && r.free[k].info().has_prior_range());
    clear += leans ? 0 : 1;
  }
  md << "- extended: spectra with every parameter inside its measured range: " << entries.size() << " of "
     << entries.size() << " (the ranges are the fit's bounds); with none on an end of its range: " << clear
     << " of " << entries.size() << " (" << fmt(100.0 * static_cast<double>(clear) / static_cast<double>(entries.size()), "%.0f")
     << " %).\n";
}

// One figure for the whole set: in each skin-tone bin the spectrum whose `--model extended` RMS
// is the bin's median (the upper one of an even count), measured (points) and fitted (line).
// Returns false when no bin has a spectrum.
bool write_tone_bin_plot(const std::vector<MeasuredEntry>& entries, const std::string& path) {
  static const std::array<std::array<double, 3>, 6> colours = {
      {{0.85, 0.55, 0.1}, {0.8, 0.25, 0.15}, {0.55, 0.2, 0.55}, {0.15, 0.45, 0.75}, {0.1, 0.55, 0.3}, {0.2, 0.2, 0.2}}};
  plot::Figure f;
  f.title = "The median fit of each skin-tone bin (--model extended)";
  f.y_max = 1.0;  // room for the legend above the spectra
  f.x_label = "wavelength [nm]";
  f.y_label = "reflectance";
  f.y_min = 0.0;
  std::size_t k = 0;
  for (std::string_view bin : fit::ita_bins()) {
    std::vector<const MeasuredEntry*> in = in_bin(entries, bin);
    const auto colour = colours[k++ % colours.size()];
    if (in.empty()) continue;
    std::sort(in.begin(), in.end(), [](const MeasuredEntry* a, const MeasuredEntry* b) {
      return a->extended_model.rms < b->extended_model.rms;
    });
    const MeasuredEntry& e = *in[in.size() / 2];
    const FitResult& r = e.extended_model;
    plot::Series meas{std::string(bin) + ": " + e.spectrum.name + " (n " + std::to_string(in.size()) + ")",
                      r.wavelength_nm, r.measured, colour};
    meas.markers = true;
    f.series.push_back(meas);
    f.series.push_back({"fit, RMS " + fmt(r.rms), r.wavelength_nm, r.fitted, colour});
  }
  if (f.series.empty()) return false;
  plot::save(f, path);
  return true;
}

}  // namespace

std::string default_spectra_dir() {
  const char* env = std::getenv("SKIN_SPECTRA_DIR");
  return env && *env ? std::string(env) : std::string("../shared/data/skin_spectra");
}

void write_measured_report(std::ostream& md, const std::vector<MeasuredEntry>& entries,
                           const std::string& spectra_dir, const std::string& out_dir,
                           const std::string& model_name, bool plots) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw InputError("cannot create directory '" + out_dir + "': " + ec.message());
  if (plots)  // one PNG per spectrum
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
     << "Generated by `skin fit --measured-report <dir>` (fits: skin::fit::fit_measured_spectra; "
        "report: src/app/report_measured.cpp) from the spectra under `"
     << fs::weakly_canonical(spectra_dir).string()
     << "` (every `*.csv`; metadata from `*metadata*.csv`). "
        "Each spectrum is fitted over 400-700 nm with the " << model_name << " R_d (docs/fit.md):\n\n"
     << "- **paper**: C_m, beta_m, C_h (the paper's model; rho_s does not enter R_d);\n"
     << "- **+rho_s**: the four parameters, rho_s through a constant specular term rho_s F, F = 0.028 "
        "(the measurement including the surface reflection);\n"
     << "- **extended**: +rho_s and the extended terms epidermal blood, beta-carotene, bilirubin, "
        "epidermis thickness, oxygenation, a scale of sigma_s' and the dermis' vessel radius (packaging).\n\n"
     << "RMS in reflectance units over the measured samples in 400-700 nm.";
  if (std::any_of(entries.begin(), entries.end(), [](const MeasuredEntry& e) { return e.used_in_paper; }))
    md << " Spectra marked * are the four the paper compares against (Fig. 9: Vrhel 82, 95, 110, 117).";
  if (const auto n = std::count_if(entries.begin(), entries.end(), [](const MeasuredEntry& e) { return e.includes_specular; }))
    md << " " << n << " of the " << entries.size()
       << " spectra are flagged in their metadata as including the surface reflection (`includes_specular`): their "
          "`--model extended` fit (\"By skin tone\" below) adds rho_s F as the +rho_s fit does.";
  md << "\n\n";
  md << "| spectrum | description | RMS paper | RMS +rho_s | RMS extended | paper fit | extended fit |\n"
     << "|---|---|---:|---:|---:|---|---|\n";
  double worst_flagged = 0;
  for (const auto& e : entries) {
    if (e.used_in_paper) worst_flagged = std::max(worst_flagged, e.extended.rms);
    const std::string name = e.spectrum.name + (e.used_in_paper ? "*" : "");
    md << "| " << (plots ? "[" + name + "](" + e.spectrum.name + ".png)" : name) << " | "
       << e.description << " | " << fmt(e.paper.rms) << " | " << fmt(e.paper_specular.rms) << " | "
       << fmt(e.extended.rms) << " | " << describe(e.paper) << " | " << describe(e.extended) << " |\n";
  }
  md << "\nWorst extended-model RMS over the paper's four spectra: " << fmt(worst_flagged) << ".\n\n";
  // Summary over all spectra: medians and how many reach RMS < fit::kGoodFitRms (0.02).
  auto summary = [&](const char* name, auto member) {
    std::vector<double> v;
    for (const auto& e : entries) v.push_back((e.*member).rms);
    std::sort(v.begin(), v.end());
    const auto below = std::count_if(v.begin(), v.end(), [](double x) { return x < fit::kGoodFitRms; });
    md << "| " << name << " | " << fmt(v[v.size() / 2]) << " | " << fmt(v.back()) << " | " << below << " / "
       << v.size() << " |\n";
  };
  md << "| model | median RMS | worst RMS | RMS < " << fmt(fit::kGoodFitRms, "%g") << " |\n|---|---:|---:|---:|\n";
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
  write_tone_bins(md, entries);
  if (write_tone_bin_plot(entries, (fs::path(out_dir) / "tone_bins.png").string()))
    md << "\n![the median fit of each skin-tone bin](tone_bins.png)\n";
  if (plots && std::any_of(entries.begin(), entries.end(), [](const MeasuredEntry& e) { return e.used_in_paper; })) {
    md << "\n## Plots of the paper's four spectra\n\n";
    for (const auto& e : entries)
      if (e.used_in_paper) md << "![" << e.spectrum.name << "](" << e.spectrum.name << ".png)\n\n";
  } else {
    md << "\n";
  }
  md << "## Extended fits (all parameters, one standard deviation from the Jacobian)\n\n";
  for (const auto& e : entries) {
    md << "- " << e.spectrum.name << ": ";
    for (std::size_t i = 0; i < e.extended.free.size(); ++i)
      md << (i ? ", " : "") << key(e.extended.free[i]) << " " << fmt(get(e.extended.parameters, e.extended.free[i]), "%.4g")
         << (e.extended.at_bound[i] ? " (bound)" : " ± " + fmt(e.extended.uncertainty[i], "%.2g"));
    md << "\n";
  }
}

std::vector<MeasuredEntry> write_measured_report(const std::string& spectra_dir,
                                                 const std::string& out_dir,
                                                 const std::string& solver, bool plots) {
  std::vector<MeasuredEntry> entries =
      fit::fit_measured_spectra(spectra_dir, fit::forward_model(solver));
  write_measured_report(entries, spectra_dir, out_dir, solver, plots);
  return entries;
}

void write_measured_report(const std::vector<MeasuredEntry>& entries,
                           const std::string& spectra_dir, const std::string& out_dir,
                           const std::string& solver, bool plots) {
  std::ostringstream md;
  write_measured_report(md, entries, spectra_dir, out_dir, solver, plots);
  util::io::write_file_atomic((std::filesystem::path(out_dir) / "README.md").string(), md.str());
}

}  // namespace skin::cli
