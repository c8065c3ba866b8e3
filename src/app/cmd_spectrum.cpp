// skin spectrum / skin color: total diffuse reflectance R_d(lambda), layer coefficients, colour.
#include "common.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/plot/plot.hpp"

namespace skin::cli {

namespace {
json spectrum_json(const SkinSpectrum& s, const std::string& preset) {
  json j;
  j["preset"] = preset;
  j["parameters"] = to_json(s.parameters);
  j["solver"] = s.solver;
  j["units"] = {{"wavelength_nm", "nm"}, {"sigma_a", "1/mm"}, {"sigma_s_prime", "1/mm"}, {"R_d", "1"}};
  j["wavelength_nm"] = s.grid.values();
  j["R_d"] = s.R_d.values;
  j["epidermis"] = {{"sigma_a", s.epidermis_sigma_a.values},
                    {"sigma_s_prime", s.epidermis_sigma_s_prime.values},
                    {"thickness_mm", s.parameters.epidermis_thickness}};
  j["dermis"] = {{"sigma_a", s.dermis_sigma_a.values},
                 {"sigma_s_prime", s.dermis_sigma_s_prime.values}};
  j["color"] = to_json(s.color);
  return j;
}
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
    std::string text;
    const std::vector<std::string> header = {"wavelength_nm", "R_d", "epidermis.sigma_a",
                                             "epidermis.sigma_s_prime", "dermis.sigma_a",
                                             "dermis.sigma_s_prime"};
    const std::vector<std::vector<double>> cols = {grid.values(), s.R_d.values,
                                                   s.epidermis_sigma_a.values,
                                                   s.epidermis_sigma_s_prime.values,
                                                   s.dermis_sigma_a.values,
                                                   s.dermis_sigma_s_prime.values};
    switch (o->out.resolve()) {
      case Format::json: text = spectrum_json(s, o->params.preset).dump(2) + "\n"; break;
      case Format::csv: text = format_csv(header, cols); break;
      case Format::table: text = format_table(header, cols) + "\n" + color_table(s.color); break;
    }
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
    o->out.emit(text);
  });
}

void register_color(CLI::App& app) {
  struct Opts {
    ParameterOptions params;
    GridOptions grid;
    SolverOption solver;
    OutputOptions out;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "color", "Colour of the skin's total diffuse reflectance: CIE XYZ (D65, 2-degree), linear "
               "sRGB (white-balanced: a perfect reflector is 1, 1, 1), 8-bit sRGB, hex, CIELAB");
  o->params.add_to(*sub);
  o->grid.add_to(*sub);
  o->solver.add_to(*sub);
  o->out.add_to(*sub);
  sub->callback([o] {
    const SkinParameters p = o->params.resolve();
    const SkinSpectrum s = skin_spectrum(p, o->grid.resolve(), o->solver.model());
    warn_if_totals_invalid(p, o->grid.resolve(), o->solver.model());
    std::string text;
    switch (o->out.resolve()) {
      case Format::json: {
        json j;
        j["preset"] = o->params.preset;
        j["parameters"] = to_json(s.parameters);
        j["solver"] = s.solver;
        j["color"] = to_json(s.color);
        text = j.dump(2) + "\n";
        break;
      }
      case Format::csv:
        text = format_csv({"X", "Y", "Z", "r_linear", "g_linear", "b_linear", "r8", "g8", "b8", "L", "a", "b"},
                          {{s.color.XYZ.X}, {s.color.XYZ.Y}, {s.color.XYZ.Z}, {s.color.srgb_linear.r},
                           {s.color.srgb_linear.g}, {s.color.srgb_linear.b}, {double(s.color.srgb8[0])},
                           {double(s.color.srgb8[1])}, {double(s.color.srgb8[2])}, {s.color.lab.L},
                           {s.color.lab.a}, {s.color.lab.b}});
        break;
      case Format::table: text = color_table(s.color); break;
    }
    o->out.emit(text);
  });
}

void register_presets(CLI::App& app) {
  auto fmt = std::make_shared<OutputOptions>();
  CLI::App* sub = app.add_subcommand("presets", "List the named parameter sets of the paper");
  fmt->add_to(*sub);
  sub->callback([fmt] {
    std::string text;
    if (fmt->resolve() == Format::json) {
      json j = json::array();
      for (const auto& p : presets())
        j.push_back({{"name", p.name}, {"description", p.description}, {"parameters", to_json(p.parameters)}});
      text = j.dump(2) + "\n";
    } else {
      for (const auto& p : presets()) text += p.name + std::string(12 - p.name.size(), ' ') + p.description + "\n";
    }
    fmt->emit(text);
  });
}

}  // namespace skin::cli
