// skin illuminants: the CIE illuminants with their white points; --compare: the colour of every
// preset under some of them, spectral against RGB rendering (CIEDE2000), and --swatches the grid.
#include <cstdio>

#include "common.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/plot/plot.hpp"
#include "skin/util/error.hpp"

namespace skin::cli {

namespace {

std::string fixed(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// Each illuminant's white point on the grid CIE 015:2018 computes them on (5 nm, 380-780 nm), and
// its colour as a light in white-balanced linear sRGB (Colorimetry::illuminant_rgb).
Result list_result() {
  const WavelengthGrid cie_grid(380, 780, 5);
  Result result;
  result.document = json::array();
  Column name{"name", {}, {}}, x{"x", {}, {}}, y{"y", {}, {}}, r{"light_srgb_linear.r", {}, {}},
      g{"light_srgb_linear.g", {}, {}}, b{"light_srgb_linear.b", {}, {}}, description{"description", {}, {}};
  std::vector<std::vector<std::string>> rows{{"name", "x", "y", "light (linear sRGB)", "description"}};
  for (const std::string& n : color::illuminant_names()) {
    const color::Illuminant& il = color::find_illuminant(n);
    const color::Colorimetry cm(cie_grid, il);
    const color::Xyz w = cm.white();
    const double sum = w.X + w.Y + w.Z;
    const Rgb light = cm.illuminant_rgb();
    result.document.push_back({{"name", n},
                               {"description", il.description()},
                               {"x", w.X / sum},
                               {"y", w.Y / sum},
                               {"white_XYZ", {w.X, w.Y, w.Z}},
                               {"light_srgb_linear", {light.r, light.g, light.b}}});
    name.text.push_back(n);
    description.text.push_back(il.description());
    x.numbers.push_back(w.X / sum);
    y.numbers.push_back(w.Y / sum);
    r.numbers.push_back(light.r);
    g.numbers.push_back(light.g);
    b.numbers.push_back(light.b);
    rows.push_back({n, fixed(w.X / sum, 5), fixed(w.Y / sum, 5),
                    fixed(light.r, 3) + " " + fixed(light.g, 3) + " " + fixed(light.b, 3), il.description()});
  }
  result.columns = {name, x, y, r, g, b, description};
  result.table = format_text_table(rows) +
                 "x, y: CIE 1931 2-degree, 5 nm 380-780 nm. light: the illuminant's colour in the "
                 "white-balanced linear sRGB of an RGB renderer (Y = 1; D65 = 1 1 1)\n";
  return result;
}

}  // namespace

void register_illuminants(CLI::App& app) {
  struct Opts {
    bool compare = false;
    std::vector<std::string> illuminants;
    std::string swatches;
    GridOptions grid;
    SolverOption solver;
    OutputOptions out;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "illuminants",
      "The CIE illuminants (CIE 015:2018 tables) with their white points; --compare: the colour of "
      "every preset under them, spectral and RGB rendering, and their CIEDE2000 difference");
  sub->add_flag("--compare", o->compare,
                "The presets under each --illuminant: spectral colour against RGB rendering (the "
                "skin's RGB albedo under D65 times the light's RGB), for a uniformly lit half-space");
  sub->add_option("--illuminant", o->illuminants,
                  "With --compare: an illuminant to compare under (repeatable; default D65, D50, A, "
                  "FL2, FL11, LED-B3)")
      ->transform(illuminant_name());
  sub->add_option("--swatches", o->swatches,
                  "With --compare: also draw the presets x illuminants as swatches to FILE.png or "
                  "FILE.svg (left: spectral, right: RGB rendering)")
      ->group("Output");
  o->grid.add_to(*sub);
  o->solver.add_to(*sub);
  o->out.add_to(*sub);
  sub->callback([o, sub] {
    if (!o->compare) {
      for (const char* flag : {"--illuminant", "--swatches", "--solver", "--lambda-min", "--lambda-max", "--lambda-step"})
        if (sub->count(flag) > 0)
          throw InputError(std::string(flag) + " is given without --compare: it applies to the comparison only");
      o->out.write(list_result());
      return;
    }
    std::vector<std::string> names = o->illuminants;
    if (names.empty()) names = {"D65", "D50", "A", "FL2", "FL11", "LED-B3"};
    const WavelengthGrid grid = o->grid.resolve();
    const color::Colorimetry d65(grid, color::find_illuminant(color::kSrgbWhite));
    std::vector<color::Colorimetry> under;
    for (const std::string& n : names) under.emplace_back(grid, color::find_illuminant(n));

    Result result;
    result.document["solver"] = o->solver.name;
    result.document["method"] =
        "uniformly lit half-space; spectral: XYZ of R_d times the illuminant; rgb_rendering: the "
        "skin's white-balanced linear sRGB under D65 times the illuminant's light colour; both "
        "CIELAB relative to the illuminant's white; delta_e_2000 between them";
    result.document["illuminants"] = names;
    json& rows = result.document["colors"] = json::array();
    Column preset_col{"preset", {}, {}}, illum_col{"illuminant", {}, {}}, hex{"hex", {}, {}},
        hex_rgb{"rgb_rendering.hex", {}, {}}, dE{"delta_e_2000", {}, {}};
    std::vector<Column> lab(6);
    const char* lab_names[6] = {"lab.L", "lab.a", "lab.b", "rgb_rendering.lab.L", "rgb_rendering.lab.a",
                                "rgb_rendering.lab.b"};
    for (int k = 0; k < 6; ++k) lab[static_cast<std::size_t>(k)].name = lab_names[k];
    std::vector<std::string> header{"delta_e_2000"};
    header.insert(header.end(), names.begin(), names.end());
    std::vector<std::vector<std::string>> table{header};
    plot::SwatchGrid fig;
    fig.title = "Presets under CIE illuminants: spectral (left) | RGB rendering (right), CIEDE2000";
    fig.columns = names;
    auto encoded = [](const color::ColorSummary& c) {
      return std::array<double, 3>{c.srgb8[0] / 255.0, c.srgb8[1] / 255.0, c.srgb8[2] / 255.0};
    };
    for (const auto& preset : presets()) {
      const SkinSpectrum s = skin_spectrum(preset.parameters, grid, o->solver.model());
      std::vector<std::string> line{preset.name};
      fig.rows.push_back(preset.name);
      for (std::size_t j = 0; j < names.size(); ++j) {
        const color::RgbVsSpectral c = color::rgb_vs_spectral(d65, under[j], s.R_d);
        rows.push_back({{"preset", preset.name},
                        {"illuminant", names[j]},
                        {"color", to_json(c.spectral)},
                        {"rgb_rendering", to_json(c.rgb)},
                        {"delta_e_2000", c.delta_e_2000}});
        preset_col.text.push_back(preset.name);
        illum_col.text.push_back(names[j]);
        hex.text.push_back(c.spectral.hex);
        hex_rgb.text.push_back(c.rgb.hex);
        const color::Lab* labs[2] = {&c.spectral.lab, &c.rgb.lab};
        for (std::size_t k = 0; k < 6; ++k) {
          const color::Lab& l = *labs[k / 3];
          lab[k].numbers.push_back(k % 3 == 0 ? l.L : (k % 3 == 1 ? l.a : l.b));
        }
        dE.numbers.push_back(c.delta_e_2000);
        line.push_back(fixed(c.delta_e_2000, 2));
        fig.cells.push_back({encoded(c.spectral), encoded(c.rgb),
                             c.spectral.hex + " | " + fixed(c.delta_e_2000, 2)});
      }
      table.push_back(line);
    }
    result.columns = {preset_col, illum_col, hex, hex_rgb};
    result.columns.insert(result.columns.end(), lab.begin(), lab.end());
    result.columns.push_back(dE);
    result.table = format_text_table(table);
    if (!o->swatches.empty()) {
      fig.note = "Uniformly lit half-space, solver " + o->solver.name + ", " +
                 std::to_string(static_cast<int>(grid.lambda_min())) + "-" +
                 std::to_string(static_cast<int>(grid.lambda_max())) +
                 " nm. Spectral: R_d x illuminant. RGB rendering: RGB albedo under D65 x light RGB.\n"
                 "sRGB after the Bradford adaptation to D65; caption: spectral hex | CIEDE2000 "
                 "(CIELAB relative to the illuminant's white).";
      plot::save(fig, o->swatches);
    }
    o->out.write(result);
  });
}

SKIN_REGISTER_COMMAND(45, register_illuminants);

}  // namespace skin::cli
