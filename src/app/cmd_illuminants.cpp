// skin illuminants: the CIE illuminants with their white points; --compare: the colour of every
// preset under some of them, spectral against RGB rendering (CIEDE2000), and --swatches the grid.
#include "common.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/plot/plot.hpp"
#include "skin/util/error.hpp"

namespace skin::cli {

using skin::util::InputError;

using skin::model::SkinSpectrum;
using skin::model::skin_spectrum;

using skin::physics::WavelengthGrid;
using skin::physics::presets;

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
      o->out.write(schema::illuminants_result());
      return;
    }
    std::vector<std::string> names = o->illuminants;
    if (names.empty()) names = {"D65", "D50", "A", "FL2", "FL11", "LED-B3"};
    const WavelengthGrid grid = o->grid.resolve();
    const color::Colorimetry d65(grid, color::find_illuminant(color::kSrgbWhite));
    std::vector<color::Colorimetry> under;
    for (const std::string& n : names) under.emplace_back(grid, color::find_illuminant(n));

    schema::IlluminantComparison comparison{o->solver.name, names, {}};
    plot::SwatchGrid fig;
    fig.title = "Presets under CIE illuminants: spectral (left) | RGB rendering (right), CIEDE2000";
    fig.columns = names;
    auto encoded = [](const color::ColorSummary& c) {
      return std::array<double, 3>{c.srgb8[0] / 255.0, c.srgb8[1] / 255.0, c.srgb8[2] / 255.0};
    };
    for (const auto& preset : presets()) {
      const SkinSpectrum s = skin_spectrum(preset.parameters, grid, o->solver.model());
      schema::IlluminantComparison::Row& row = comparison.rows.emplace_back();
      row.preset = preset.name;
      fig.rows.push_back(preset.name);
      for (std::size_t j = 0; j < names.size(); ++j) {
        const color::RgbVsSpectral& c = row.colors.emplace_back(color::rgb_vs_spectral(d65, under[j], s.R_d));
        fig.cells.push_back({encoded(c.spectral), encoded(c.rgb),
                             c.spectral.hex + " | " + schema::format_fixed(c.delta_e_2000, 2)});
      }
    }
    if (!o->swatches.empty()) {
      fig.note = "Uniformly lit half-space, solver " + o->solver.name + ", " +
                 std::to_string(static_cast<int>(grid.lambda_min())) + "-" +
                 std::to_string(static_cast<int>(grid.lambda_max())) +
                 " nm. Spectral: R_d x illuminant. RGB rendering: RGB albedo under D65 x light RGB.\n"
                 "sRGB after the Bradford adaptation to D65; caption: spectral hex | CIEDE2000 "
                 "(CIELAB relative to the illuminant's white).";
      plot::save(fig, o->swatches);
    }
    o->out.write(schema::illuminant_comparison_result(comparison));
  });
}

SKIN_REGISTER_COMMAND(45, register_illuminants);

}  // namespace skin::cli
