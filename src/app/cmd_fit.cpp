// skin fit: the inverse model (docs/fit.md). Parameters from a measured reflectance spectrum,
// from an sRGB colour, or per pixel from an albedo texture; and the measured-spectra report.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "color_fit_schema.hpp"
#include "common.hpp"
#include "fit_schema.hpp"
#include "progress.hpp"
#include "report_measured.hpp"
#include "skin/fit/color_fit.hpp"
#include "skin/fit/fit.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"
#include "skin/plot/plot.hpp"

namespace skin::cli {

using skin::util::InputError;
using skin::util::ProgressCallback;

using skin::physics::WavelengthGrid;

namespace {

struct FitOpts {
  ParameterOptions params;
  OutputOptions out;
  std::string spectrum, column, srgb, hex, texture, report_dir, spectra_dir;
  std::string free, plot, fitted, preview;
  std::string model = "paper";
  SolverOption solver;
  std::vector<std::string> bounds;
  bool includes_specular = false, uncertainty = false, no_plots = false;
  double lambda_min = 400, lambda_max = 700;
  double port_radius = 0, beam_radius = 0;
  bool through_port = false;  // --port-radius given
  double blend_prior = 0.7, blend_weight = 0.2;
};

fit::ForwardModel forward_model(const SolverOption& solver) { return fit::forward_model(solver.model()); }

std::vector<std::pair<fit::Parameter, fit::Bounds>> parse_bounds(const std::vector<std::string>& specs) {
  std::vector<std::pair<fit::Parameter, fit::Bounds>> out;
  for (const auto& s : specs) {
    const auto eq = s.find('='), colon = s.find(':');
    if (eq == std::string::npos || colon == std::string::npos || colon < eq)
      throw InputError("bound = '" + s + "' must look like NAME=LO:HI (e.g. melanin=0:0.3)");
    const fit::Parameter p = fit::parse_parameter(s.substr(0, eq));
    fit::Bounds b;
    try {
      std::size_t u1 = 0, u2 = 0;
      const std::string lo = s.substr(eq + 1, colon - eq - 1), hi = s.substr(colon + 1);
      b.lo = std::stod(lo, &u1);
      b.hi = std::stod(hi, &u2);
      if (u1 != lo.size() || u2 != hi.size()) throw std::invalid_argument("trailing");
    } catch (const std::exception&) {
      throw InputError("bound = '" + s + "': LO and HI must be numbers");
    }
    if (!(b.lo < b.hi)) throw InputError("bound = '" + s + "': need LO < HI");
    out.emplace_back(p, b);
  }
  return out;
}

std::string fitted_text(const fit::FitResult& r, const std::string& path) {
  std::vector<double> resid(r.fitted.size());
  for (std::size_t i = 0; i < resid.size(); ++i) resid[i] = r.fitted[i] - r.measured[i];
  if (util::io::extension(path) == "json") {
    json j;
    j["wavelength_nm"] = r.wavelength_nm;
    j["measured"] = r.measured;
    j["R"] = r.fitted;
    j["residual"] = resid;
    return j.dump(2) + "\n";
  }
  if (util::io::extension(path) != "csv")
    throw InputError("fitted = '" + path + "': the extension must be .csv or .json");
  return format_csv({"wavelength_nm", "measured", "R", "residual"}, {r.wavelength_nm, r.measured, r.fitted, resid});
}

void run_spectrum(const FitOpts& o) {
  // Everything that can fail on input is checked before anything is written.
  if (!o.plot.empty() && util::io::extension(o.plot) != "png" && util::io::extension(o.plot) != "svg")
    throw InputError("plot = '" + o.plot + "': the extension must be .png or .svg");
  if (!o.fitted.empty() && util::io::extension(o.fitted) != "csv" && util::io::extension(o.fitted) != "json")
    throw InputError("fitted = '" + o.fitted + "': the extension must be .csv or .json");
  fit::SpectrumFitOptions opt;
  opt.start = o.params.resolve();
  fit::use_fit_model(opt, fit::parse_fit_model(o.model));
  if (!o.free.empty()) opt.free = fit::parse_parameter_list(o.free);
  opt.includes_specular = o.includes_specular;
  opt.lambda_min = o.lambda_min;
  opt.lambda_max = o.lambda_max;
  opt.bounds = parse_bounds(o.bounds);
  opt.model = o.through_port ? fit::forward_model_through_port(o.solver.model(), o.port_radius, o.beam_radius)
                             : forward_model(o.solver);
  (void)o.out.resolve();  // a contradicting --format fails before the fit
  const fit::MeasuredSpectrum m = fit::read_spectrum(o.spectrum, o.column);
  const fit::FitResult r = fit::SpectrumFitter(opt).fit(m);

  const Result result =
      schema::spectrum_fit_result(m, r, o.solver.name, o.includes_specular, o.port_radius, o.beam_radius);
  if (!o.fitted.empty()) util::io::write_file_atomic(o.fitted, fitted_text(r, o.fitted));
  if (!o.plot.empty()) {
    plot::Figure f;
    char rms[32];
    std::snprintf(rms, sizeof rms, "%.4f", r.rms);
    f.title = "Fit of " + std::filesystem::path(m.name).filename().string() + " (" + o.solver.name + ", RMS " + rms + ")";
    f.x_label = "wavelength [nm]";
    f.y_label = "reflectance";
    f.y_min = 0.0;
    plot::Series meas{"measured", r.wavelength_nm, r.measured, {0.1, 0.1, 0.1}};
    meas.markers = true;
    f.series.push_back(meas);
    f.series.push_back({"model", r.wavelength_nm, r.fitted, {0.8, 0.25, 0.15}});
    plot::save(f, o.plot);
  }
  o.out.write(result);
}

// Options shared by the colour and the texture fits.
fit::ColorFitOptions color_fit_options(const FitOpts& o) {
  fit::ColorFitOptions opt;
  opt.start = o.params.resolve();
  fit::use_fit_model(opt, fit::parse_fit_model(o.model));
  if (!o.free.empty()) opt.free = fit::parse_parameter_list(o.free);
  opt.melanin_blend_prior = o.blend_prior;
  opt.melanin_blend_weight = o.blend_weight;
  opt.bounds = parse_bounds(o.bounds);
  opt.model = forward_model(o.solver);
  return opt;
}

void run_color(const FitOpts& o) {
  const fit::ColorFitOptions opt = color_fit_options(o);
  const color::Rgb target = o.hex.empty() ? fit::parse_srgb8(o.srgb) : fit::parse_hex(o.hex);
  const fit::ColorFitResult r = fit::ColorFitter(opt).fit(target);
  if (r.delta_e > 1.0)
    std::cerr << "skin fit: warning: the closest model colour is " << r.delta_e
              << " dE2000 away: the target is outside the colours the model reaches with the "
                 "fixed parameters\n";
  o.out.write(schema::color_fit_result(r, target, o.blend_prior, o.blend_weight));
}

// The maps side by side as a PNG (the four, then the extended model's others), each on its own
// range: the parameters' from the 1st to the 99th percentile of their texels (a few texels at a
// bound would otherwise flatten the rest), the error from 0 to its 99th percentile; values
// beyond take the ends' colours.
void write_maps_preview(const fit::ParameterMaps& maps, const std::string& texture, const std::string& path) {
  plot::MapSheet sheet;
  sheet.title = "skin fit --texture " + std::filesystem::path(texture).filename().string() + ": parameter maps (" +
                std::to_string(maps.width) + " x " + std::to_string(maps.height) + "; ranges: 1st-99th percentile)";
  auto panel = [&](const std::string& title, const std::vector<float>& v, bool from_zero) {
    plot::MapPanel p{title, maps.width, maps.height, v, 0, 1};
    std::vector<float> finite;
    finite.reserve(v.size());
    for (float x : v)
      if (std::isfinite(x)) finite.push_back(x);
    if (!finite.empty()) {
      auto at = [&finite](double q) {
        const auto k = static_cast<std::size_t>(q * double(finite.size() - 1));
        std::nth_element(finite.begin(), finite.begin() + static_cast<std::ptrdiff_t>(k), finite.end());
        return static_cast<double>(finite[k]);
      };
      p.hi = at(0.99);
      p.lo = from_zero ? 0.0 : at(0.01);
      if (!(p.hi > p.lo)) p.hi = p.lo + 1e-9;
    }
    sheet.panels.push_back(std::move(p));
  };
  panel("melanin (C_m)", maps.melanin, false);
  panel("melanin_blend (beta_m)", maps.melanin_blend, false);
  panel("hemoglobin (C_h)", maps.hemoglobin, false);
  panel("error (CIEDE2000)", maps.error, true);
  // The extended model's other maps (epidermis_thickness, ...) after them.
  for (std::size_t k = 0; k < maps.more_parameters.size() && k < maps.more.size(); ++k)
    panel(std::string(fit::key(maps.more_parameters[k])), maps.more[k], false);
  // With --uncertainty, one standard deviation of each free parameter (from 0).
  for (std::size_t k = 0; k < maps.uncertainty_parameters.size() && k < maps.uncertainty.size(); ++k)
    panel(fit::uncertainty_channel(maps.uncertainty_parameters[k]) + " (1 sd)", maps.uncertainty[k], true);
  if (sheet.panels.size() > 4) sheet.columns = sheet.panels.size() > 9 ? 4 : 3;
  char note[160];
  std::snprintf(note, sizeof note, "mean error %.2f dE2000, %.1f %% of texels below 1; docs/parameter-maps.md",
                maps.mean_error, 100.0 * maps.fraction_below_1);
  sheet.note = note;
  plot::save(sheet, path);
}

void run_texture(const FitOpts& o) {
  if (o.out.output.empty()) throw InputError("texture: give the output parameter maps with -o FILE.exr");
  if (util::io::extension(o.out.output) != "exr")
    throw InputError("output = '" + o.out.output + "': parameter maps are written as .exr");
  if (!o.preview.empty() && util::io::extension(o.preview) != "png")
    throw InputError("preview = '" + o.preview + "': the maps' preview is written as .png");
  if (!o.preview.empty() && o.preview == o.out.output)
    throw InputError("preview = '" + o.preview + "' is the output file too: give the preview another name");
  const fit::ColorFitOptions opt = color_fit_options(o);
  const image::Image img = image::read_image(o.texture);
  const fit::TextureFitter fitter(opt);
  // The bars are empty unless stderr is a terminal; each starts its clock when made. (A table
  // read, not built, reports no nodes.)
  const ProgressCallback nodes = progress_bar("table nodes");
  if (nodes) std::cerr << "skin fit: building the colour table...\r" << std::flush;
  fitter.prepare(nodes);
  const fit::ParameterMaps maps = fitter.fit(img, progress_bar("distinct colours"), o.uncertainty);
  fit::write_parameter_maps(maps, o.out.output);
  if (!o.preview.empty()) write_maps_preview(maps, o.texture, o.preview);
  // -o is the EXR: the summary goes to standard output in --format (table on a terminal).
  OutputOptions summary = o.out;
  summary.output.clear();
  summary.write(schema::texture_fit_result(maps, o.texture, o.out.output));
}

void run_report(const FitOpts& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(o.spectra_dir, ec))
    throw InputError("spectra-dir = '" + o.spectra_dir +
                     "' is not a directory: give the measured skin spectra with --spectra-dir DIR "
                     "or SKIN_SPECTRA_DIR");
  write_measured_report(o.spectra_dir, o.report_dir, o.solver.name, !o.no_plots);
  std::cout << "wrote " << (fs::path(o.report_dir) / "README.md").string()
            << (o.no_plots ? "\n" : " and one PNG per spectrum\n");
}

}  // namespace

void register_fit(CLI::App& app) {
  auto o = std::make_shared<FitOpts>();
  o->spectra_dir = default_spectra_dir();
  CLI::App* sub = app.add_subcommand(
      "fit",
      "Inverse model: recover skin parameters from a measured reflectance spectrum (--spectrum), "
      "an sRGB colour (--srgb/--hex) or an albedo texture (--texture); or write the "
      "measured-spectra report (--measured-report). See docs/fit.md");
  auto* g_in = "Input (exactly one)";
  auto* o_spec = sub->add_option("--spectrum", o->spectrum,
                                 "Measured reflectance CSV: wavelength [nm], reflectance 0-1; must cover 450-650 nm")
                     ->group(g_in);
  auto* o_srgb = sub->add_option("--srgb", o->srgb, "Target colour R,G,B (8-bit sRGB, 0-255)")->group(g_in);
  auto* o_hex = sub->add_option("--hex", o->hex, "Target colour RRGGBB (8-bit sRGB)")->group(g_in);
  auto* o_tex = sub->add_option("--texture", o->texture,
                                "Albedo texture (PNG, 8 or 16 bit, sRGB-encoded) -> per-pixel maps, -o FILE.exr")
                    ->group(g_in);
  auto* o_rep = sub->add_option("--measured-report", o->report_dir,
                                "Fit every spectrum under --spectra-dir and write README.md + PNGs to DIR")
                    ->group(g_in);
  for (auto* a : {o_spec, o_srgb, o_hex, o_tex, o_rep})
    for (auto* b : {o_spec, o_srgb, o_hex, o_tex, o_rep})
      if (a != b) a->excludes(b);
  sub->add_flag("--no-plots", o->no_plots,
                "Measured report: README.md only, without the PNG per spectrum (for sets of many spectra)")
      ->needs(o_rep)
      ->group(g_in);
  sub->add_option("--spectra-dir", o->spectra_dir,
                  "Directory of measured spectra for --measured-report (default: $SKIN_SPECTRA_DIR, "
                  "else ../shared/data/skin_spectra from the current directory)")
      ->capture_default_str()->group(g_in);
  auto* o_col = sub->add_option("--column", o->column, "Reflectance column of a multi-column CSV")->group(g_in);

  auto* g_fit = "Fit";
  auto* o_model = sub->add_option("--model", o->model,
                  "Parameter set: paper (C_m, beta_m, C_h; the default) or extended (+ oxygenation, epidermis "
                  "thickness, the dermis' and both layers' scattering scales; spectra also beta-carotene, "
                  "epidermal blood), each kept in its range with a weak prior (docs/fit.md)")
      ->capture_default_str()->group(g_fit);
  sub->add_option("--free", o->free,
                  "Parameters to fit, comma-separated names or the paper's symbols (default "
                  "melanin,melanin-blend,hemoglobin); "
                  "extended: epidermal-hemoglobin, beta-carotene, bilirubin, epidermis-thickness, "
                  "dermis-scattering-scale, oxygenation, scattering-scale, blood-vessel-radius")
      ->group(g_fit);
  auto* o_port = sub->add_option("--port-radius", o->port_radius,
                                 "Spectrum fit: the measurement collects only over a disc of this radius [mm] "
                                 "around the beam (an integrating sphere's sample port; docs/fit.md)")
                     ->needs(o_spec)
                     ->group(g_fit);
  sub->add_option("--beam-radius", o->beam_radius,
                  "Spectrum fit with --port-radius: the light enters evenly over a concentric disc of this "
                  "radius [mm], at most the port's (default 0: a pencil beam at the centre)")
      ->needs(o_port)
      ->group(g_fit);
  auto* o_specular = sub->add_flag("--includes-specular", o->includes_specular,
                "The measurement includes the surface reflection: add rho_s F (F = Fresnel at normal "
                "incidence, 0.028) and fit oiliness")
      ->group(g_fit);
  sub->add_option("--bound", o->bounds, "Search interval NAME=LO:HI (repeatable; NAME or symbol), e.g. melanin=0:0.3")->group(g_fit);
  auto* o_lmin = sub->add_option("--fit-lambda-min", o->lambda_min, "Fit only samples at or above this wavelength [nm]")
      ->capture_default_str()->group(g_fit);
  auto* o_lmax = sub->add_option("--fit-lambda-max", o->lambda_max, "Fit only samples at or below this wavelength [nm]")
      ->capture_default_str()->group(g_fit);
  auto* o_prior = sub->add_option("--melanin-blend-prior", o->blend_prior,
                  "Colour fits: beta_m the regulariser pulls toward, [0, 1]")->capture_default_str()->group(g_fit);
  auto* o_weight = sub->add_option("--melanin-blend-weight", o->blend_weight,
                  "Colour fits: regulariser weight [Lab units per unit beta_m], >= 0")->capture_default_str()->group(g_fit);
  o->solver.add_to(*sub)->group(g_fit);

  o->params.add_to(*sub);
  o->out.own_extensions = {"exr"};  // --texture's parameter maps
  o->out.add_to(*sub);
  auto* o_plot = sub->add_option("--plot", o->plot, "Spectrum fit: draw measurement and model to FILE.png or FILE.svg")->group("Output");
  auto* o_fitted = sub->add_option("--fitted", o->fitted, "Spectrum fit: write the fitted spectrum to FILE.csv or FILE.json")->group("Output");
  auto* o_preview = sub->add_option("--preview", o->preview,
                                    "Texture fit: also draw the four maps in false colour, side by side, to FILE.png")
                        ->group("Output");
  o_preview->needs(o_tex);
  sub->add_flag("--uncertainty", o->uncertainty,
                "Texture fit: also write one standard deviation per free parameter and texel, the channels "
                "uncertainty.<key> (docs/parameter-maps.md)")
      ->group("Output")
      ->needs(o_tex);

  // Options that only make sense for one kind of input are rejected elsewhere, before any work.
  for (auto* opt : {o_col, o_specular, o_lmin, o_lmax, o_plot, o_fitted}) opt->needs(o_spec);
  sub->callback([o, o_spec, o_srgb, o_hex, o_tex, o_rep, o_prior, o_weight, o_model, o_port] {
    o->through_port = o_port->count() > 0;
    if (o_model->count() && o_rep->count())
      throw InputError("--model applies to --spectrum, --srgb, --hex and --texture; the measured report "
                       "fits both models");
    if ((o_prior->count() || o_weight->count()) && fit::parse_fit_model(o->model) == fit::FitModel::extended)
      throw InputError("--melanin-blend-prior and --melanin-blend-weight apply to --model paper; the "
                       "extended model's priors are the parameter table's (docs/fit.md)");
    if ((o_prior->count() || o_weight->count()) && !(o_srgb->count() || o_hex->count() || o_tex->count()))
      throw InputError("--melanin-blend-prior and --melanin-blend-weight apply to colour fits only "
                       "(--srgb, --hex, --texture)");
    if (o_spec->count()) run_spectrum(*o);
    else if (o_srgb->count() || o_hex->count()) run_color(*o);
    else if (o_tex->count()) run_texture(*o);
    else if (o_rep->count()) run_report(*o);
    else throw InputError("fit: give one input: --spectrum, --srgb, --hex, --texture or --measured-report");
  });
}

// `skin tabulate-color-table`: the built-in tables of the texture fits.
void register_color_table(CLI::App& app) {
  auto out = std::make_shared<std::string>();
  auto model = std::make_shared<std::string>("extended");
  CLI::App* sub = app.add_subcommand(
      "tabulate-color-table",
      "Tabulate a texture fit's colour table (the colour at every node over the model's default free "
      "parameters): the data file that `skin fit --texture` reads, data/extended_color_table.csv (147 456 "
      "nodes, about 32 s on 2 cores) or with --model paper data/paper_color_table.csv (9 600 nodes, about 3 s)");
  sub->add_option("-o,--output", *out, "Output CSV file (written atomically)")->required();
  sub->add_option("--model", *model, "paper or extended (default extended)");
  sub->callback([out, model] {
    fit::ColorFitOptions opt;
    const fit::FitModel m = fit::parse_fit_model(*model);
    fit::use_fit_model(opt, m);
    const fit::TextureFitter fitter(opt, false);
    fitter.prepare(progress_bar("table nodes"));
    const fit::ColorTable& t = fitter.color_table();
    util::io::write_file_atomic(*out, t.to_csv("skin tabulate-color-table --model " + std::string(m == fit::FitModel::extended ? "extended" : "paper") +
                                               " (" + std::string(transport::kDefaultModel) + " solver)"));
    std::cout << "wrote " << *out << ": " << t.lab.size() << " nodes\n";
  });
}

SKIN_REGISTER_COMMAND(80, register_fit);
SKIN_REGISTER_COMMAND(81, register_color_table);

}  // namespace skin::cli
