// skin profile: radial diffusion profile R(r) per wavelength or per linear sRGB channel.
#include "common.hpp"
#include "progress.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/util/error.hpp"
#include "skin/plot/plot.hpp"

namespace skin::cli {

using skin::util::ProgressCallback;
using skin::util::format_number;

using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;
using skin::transport::RgbProfile;
using skin::transport::SpectralProfile;

using skin::model::skin_profile_solves;
using skin::model::skin_rgb_profile;
using skin::model::skin_spectral_profile;
using skin::model::skin_validity;

using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;

void register_profile(CLI::App& app) {
  struct Opts {
    ParameterOptions params;
    GridOptions grid;
    SolverOption solver;
    OutputOptions out;
    bool rgb = false;
    double radius_min = 1e-3, radius_max = 16.0;
    std::size_t samples = 256;
    std::string spacing = "log";
    std::string plot;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* sub = app.add_subcommand(
      "profile", "Radial profile R(r) [1/mm^2] of the two-layer skin (DJ06 section 4), per "
                 "wavelength or per linear sRGB channel");
  o->params.add_to(*sub);
  o->grid.add_to(*sub);
  o->solver.add_to(*sub);
  o->out.add_to(*sub);
  sub->add_flag("--rgb", o->rgb, "Per linear sRGB channel (r, g, b) instead of per wavelength");
  sub->add_option("--radius-min", o->radius_min, "Smallest radius [mm] (log spacing)")->capture_default_str();
  sub->add_option("--radius-max", o->radius_max, "Largest radius [mm]")->capture_default_str();
  sub->add_option("--samples", o->samples, "Number of radii")->check(whole_number(2, 1000000))->capture_default_str();
  sub->add_option("--spacing", o->spacing, "Radii spaced evenly in log r (from --radius-min) or linearly from 0")
      ->check(CLI::IsMember({"log", "linear"}))->capture_default_str();
  sub->add_option("--plot", o->plot, "Also draw the profile per RGB channel on log axes to FILE.png or FILE.svg")
      ->group("Output");
  sub->callback([o] {
    const SkinParameters p = o->params.resolve();
    const WavelengthGrid grid = o->grid.resolve();
    RadialGrid radii = o->spacing == "log" ? RadialGrid::logarithmic(o->radius_min, o->radius_max, o->samples)
                                           : RadialGrid::linear(o->radius_max, o->samples);
    ProfileSolver solver(radii);
    const transport::Model& model = o->solver.model();
    const transport::Validity validity = skin_validity(p, grid, model);
    warn_validity(model, validity);
    (void)o->out.resolve();  // a contradicting --format fails before the work
    Result result;
    RgbProfile rgb;
    // Off the accurate model's skin table each wavelength is solved (docs/benchmarks.md): said
    // before it starts, with an estimate, and a bar on a terminal.
    note_profile_solves(skin_profile_solves(p, grid, model), grid.size());
    const ProgressCallback progress = progress_bar("wavelengths");
    if (o->rgb || !o->plot.empty()) rgb = skin_rgb_profile(p, grid, solver, model, progress);
    if (o->rgb) {
      const char* names[3] = {"r", "g", "b"};
      for (int c = 0; c < 3; ++c) warn_if_negative(std::string("R(r) linear sRGB channel ") + names[c], rgb.R[c], radii.r, "mm", true);
      result = schema::rgb_profile_result(rgb, p, o->params.preset, o->solver.name, validity);
    } else {
      const SpectralProfile sp = skin_spectral_profile(p, grid, solver, model, progress);
      for (std::size_t i = 0; i < grid.size(); ++i)
        warn_if_negative("R(r) at " + format_number(grid[i]) + " nm",
                         std::vector<double>(sp.R.begin() + static_cast<std::ptrdiff_t>(i * radii.size()),
                                             sp.R.begin() + static_cast<std::ptrdiff_t>((i + 1) * radii.size())),
                         radii.r, "mm");
      result = schema::spectral_profile_result(sp, p, o->params.preset, o->solver.name, validity);
    }
    if (!o->plot.empty()) {
      plot::Figure f;
      f.title = "Radial profile, preset " + o->params.preset + " (" + o->solver.name + ")";
      f.x_label = "r [mm]";
      f.y_label = "R(r) [1/mm^2]";
      f.log_x = o->spacing == "log";
      f.log_y = true;
      const std::array<std::array<double, 3>, 3> col = {{{0.85, 0.1, 0.1}, {0.1, 0.6, 0.1}, {0.1, 0.2, 0.85}}};
      const char* names[3] = {"red (linear sRGB)", "green", "blue"};
      for (std::size_t c = 0; c < 3; ++c) f.series.push_back({names[c], radii.r, rgb.R[c], col[c]});
      plot::save(f, o->plot);
    }
    o->out.write(result);
  });
}

SKIN_REGISTER_COMMAND(20, register_profile);

}  // namespace skin::cli
