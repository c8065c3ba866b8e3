// skin spectrum / skin color: total diffuse reflectance R_d(lambda), layer coefficients, colour.
#include "common.hpp"
#include "skin/color/color.hpp"
#include "skin/fit/color_fit.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/plot/plot.hpp"

namespace skin::cli {

using skin::model::SkinSpectrum;
using skin::model::color_under;
using skin::model::skin_spectrum;
using skin::model::skin_validity;

using skin::physics::Preset;
using skin::physics::presets;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;

namespace {
// Totals only: the model's validity for them (the multipole in a layer thinner than z_r).
void warn_if_totals_invalid(const SkinParameters& p, const WavelengthGrid& grid,
                            const transport::Model& model) {
  const transport::Validity v = skin_validity(p, grid, model);
  if (!v.totals) warn_validity(model, v);
}
}  // namespace

void register_spectrum(CLI::App& app) {
  struct Opts {
    ParameterOptions params;
    GridOptions grid;
    SolverOption solver;
    OutputOptions out;
    std::string plot;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "spectrum",
      "Total diffuse reflectance R_d(lambda) of the two-layer skin, the layers' sigma_a and "
      "sigma_s_prime [1/mm], and the colour under D65");
  o->params.add_to(*sub);
  o->grid.add_to(*sub);
  o->solver.add_to(*sub);
  o->out.add_to(*sub);
  sub->add_option("--plot", o->plot, "Also draw the spectrum with its sRGB swatch to FILE.png or FILE.svg")
      ->group("Output");
  sub->callback([o] {
    const SkinParameters p = o->params.resolve();
    const WavelengthGrid grid = o->grid.resolve();
    const SkinSpectrum s = skin_spectrum(p, grid, o->solver.model());
    warn_if_totals_invalid(p, grid, o->solver.model());
    warn_if_negative("R_d", s.R_d.values, grid.values(), "nm");
    const Result result = schema::spectrum_result(s, o->params.preset);
    if (!o->plot.empty()) {
      plot::Figure f;
      f.title = "Total diffuse reflectance, preset " + o->params.preset + " (" + o->solver.name + ")";
      f.x_label = "wavelength [nm]";
      f.y_label = "R_d";
      f.y_min = 0.0;
      f.series.push_back({"R_d", grid.values(), s.R_d.values, {0.75, 0.2, 0.15}});
      f.swatches.push_back({{s.color.srgb8[0] / 255.0, s.color.srgb8[1] / 255.0, s.color.srgb8[2] / 255.0},
                            "sRGB " + s.color.hex});
      plot::save(f, o->plot);
    }
    o->out.write(result);
  });
}

void register_color(CLI::App& app) {
  struct Opts {
    ParameterOptions params;
    GridOptions grid;
    SolverOption solver;
    IlluminantOption illuminant;
    OutputOptions out;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "color", "Colour of the skin's total diffuse reflectance: CIE XYZ (2-degree) under the "
               "illuminant, linear sRGB (white-balanced: a perfect reflector is 1, 1, 1), 8-bit "
               "sRGB, hex, CIELAB");
  o->params.add_to(*sub);
  o->grid.add_to(*sub);
  o->solver.add_to(*sub);
  o->illuminant.add_to(*sub, "CIE illuminant lighting the skin (skin illuminants lists them); "
                             "other than D65, sRGB and hex after the Bradford adaptation to D65, "
                             "CIELAB relative to the illuminant's white");
  o->out.add_to(*sub);
  sub->callback([o] {
    const SkinParameters p = o->params.resolve();
    const WavelengthGrid grid = o->grid.resolve();
    const color::Illuminant& illuminant = o->illuminant.illuminant();
    const SkinSpectrum s = skin_spectrum(p, grid, o->solver.model());
    warn_if_totals_invalid(p, grid, o->solver.model());
    o->out.write(schema::color_result(s, o->params.preset, color_under(s, illuminant)));
  });
}

void register_presets(CLI::App& app) {
  struct Opts {
    OutputOptions out;
    std::string plot, swatches;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "presets", "List the named parameter sets: the paper's and the tone presets (monk-01 ... monk-10), each "
                 "with its source and its colour under D65 with the default solver");
  o->out.add_to(*sub);
  sub->add_option("--plot", o->plot,
                  "Also draw the R_d spectra of the tone presets (those with a target colour; default solver) "
                  "to FILE.png or FILE.svg");
  sub->add_option("--swatches", o->swatches,
                  "Also draw every tone preset's target colour (left) against its colour under D65 with the "
                  "default solver (right), with their CIEDE2000 difference, to FILE.png or FILE.svg");
  sub->callback([o] {
    const Result result = schema::presets_result();
    if (!o->plot.empty() || !o->swatches.empty()) {
      const WavelengthGrid grid;
      const transport::Model& model = transport::default_model();
      const color::Colorimetry cm(grid);
      plot::Figure f;
      f.title = "Tone presets: R_d with the " + std::string(model.name()) + " solver";
      f.x_label = "wavelength [nm]";
      f.y_label = "R_d";
      f.y_min = 0.0;
      f.height = 640;
      plot::SwatchGrid g;
      g.title = "Tone presets, D65";
      g.columns = {"target", std::string(model.name()) + ", dE2000"};
      auto encoded = [](const std::array<int, 3>& c) {
        return std::array<double, 3>{c[0] / 255.0, c[1] / 255.0, c[2] / 255.0};
      };
      for (const Preset& p : presets()) {
        if (p.target_hex.empty()) continue;
        const SkinSpectrum s = skin_spectrum(p.parameters, grid, model);
        const std::array<double, 3> rgb = encoded(s.color.srgb8);
        f.series.push_back({p.name, grid.values(), s.R_d.values, rgb});
        const color::ColorSummary target = color::summarize_rgb(cm, fit::parse_hex(p.target_hex));
        g.rows.push_back(p.name);
        g.cells.push_back({encoded(target.srgb8), std::nullopt, p.target_hex});
        g.cells.push_back({rgb, std::nullopt,
                           s.color.hex + "  " + schema::format_fixed(color::delta_e_2000(target.lab, s.color.lab), 2)});
      }
      g.note = "Uniformly lit half-space,\n400-700 nm; targets: Monk\nSkin Tone scale";
      if (!o->plot.empty()) plot::save(f, o->plot);
      if (!o->swatches.empty()) plot::save(g, o->swatches);
    }
    o->out.write(result);
  });
}

SKIN_REGISTER_COMMAND(10, register_spectrum);
SKIN_REGISTER_COMMAND(40, register_color);
SKIN_REGISTER_COMMAND(50, register_presets);

}  // namespace skin::cli
