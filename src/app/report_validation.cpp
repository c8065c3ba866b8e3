// The validation report of `skin validate` (report_validation.hpp): Markdown and plots of a
// skin::mc::ValidationRun.
#include "report_validation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <ostream>
#include <sstream>

#include "skin/plot/plot.hpp"
#include "skin/transport/accurate.hpp"

namespace skin::cli {

using skin::physics::Layer;
using skin::physics::LayerStack;

using mc::CaseResult;
using mc::ValidationRun;

namespace {

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string percent(double v) { return std::isfinite(v) ? fmt("%+.2f %%", 100.0 * v) : "n/a"; }

// Transport mean free path of a layer [mm].
double mfp(const Layer& l) { return 1.0 / (l.sigma_a + l.sigma_s_prime); }

std::string stack_summary(const LayerStack& s) {
  std::ostringstream os;
  os << "n_above " << s.eta_above;
  for (const auto& l : s.layers) {
    os << " | sigma_a " << fmt("%.4g", l.sigma_a) << ", sigma_s' " << fmt("%.4g", l.sigma_s_prime)
       << ", d " << (l.semi_infinite() ? std::string("inf") : fmt("%.4g", l.thickness))
       << ", n " << l.eta << ", g " << l.g;
  }
  if (!s.semi_infinite()) os << " | n_below " << s.eta_below;
  return os.str();
}

// "12.3 % (0.45 mm)", "-" without a profile, "n/a" where Monte Carlo is too noisy.
std::string profile_error_text(const CaseResult& c, std::size_t k, double r_min) {
  if (c.R[k].empty()) return "-";
  const auto [e, r] = c.max_profile_error(k, r_min);
  if (std::isnan(e)) return "n/a";
  return fmt("%.1f %%", 100 * e) + " (" + fmt("%.3g mm", r) + ")";
}

const std::array<double, 3> kColours[] = {
    {0.80, 0.15, 0.10}, {0.10, 0.35, 0.80}, {0.10, 0.60, 0.25}, {0.60, 0.20, 0.70}};

// "| case | annuli | NAME: BEYOND | WORST |..." and its separator line: the tables of annuli.
void check_table_header(std::ostream& md, const std::vector<std::string>& names,
                        const char* beyond, const char* worst) {
  md << "| case | annuli |";
  for (const auto& n : names) md << ' ' << n << ": " << beyond << " | " << worst << " |";
  md << "\n|---|---|";
  for (std::size_t k = 0; k < names.size(); ++k) md << "---|---|";
  md << '\n';
}

// Draws the case's profiles to `path`; false (nothing written) when no Monte Carlo bin has a
// meaningful estimate (too few photons).
bool plot_case(const CaseResult& cr, const std::vector<std::string>& names,
               const std::string& path) {
  plot::Figure fig;
  fig.title = cr.c.title;
  fig.x_label = "r [mm]";
  fig.y_label = "R(r) [1/mm^2]";
  fig.log_x = fig.log_y = true;
  plot::Series mc;
  mc.label = "Monte Carlo (" + fmt("%.0e", static_cast<double>(cr.mc.photons)) + " photons)";
  mc.markers = true;
  mc.rgb = {0.1, 0.1, 0.1};
  double y_max = 0;
  for (std::size_t i = 0; i < cr.mc.R.size(); ++i) {
    // Only bins with a meaningful estimate (relative standard error below 30 %).
    if (cr.mc.R[i] > 0 && cr.mc.R_se[i] < 0.3 * cr.mc.R[i]) {
      mc.x.push_back(cr.mc.r_mm[i]);
      mc.y.push_back(cr.mc.R[i]);
      y_max = std::max(y_max, cr.mc.R[i]);
    }
  }
  if (mc.x.empty()) return false;
  const double y_min = *std::min_element(mc.y.begin(), mc.y.end());
  fig.series.push_back(mc);
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (cr.R_fine[k].empty()) continue;
    plot::Series s;
    s.label = names[k];
    s.rgb = kColours[k % 4];
    s.dashed = k % 2 == 1;  // alternate, so that curves that coincide stay visible
    for (std::size_t i = 0; i < cr.R_fine[k].size(); ++i) {
      if (cr.R_fine[k][i] > 0.1 * y_min) {  // log axis: drop values <= 0 and far below the data
        s.x.push_back(cr.r_fine[i]);
        s.y.push_back(cr.R_fine[k][i]);
      }
    }
    fig.series.push_back(s);
  }
  fig.y_min = 0.5 * y_min;
  fig.y_max = 2.0 * y_max;
  plot::save(fig, path);
  return true;
}

void plot_overview(const ValidationRun& run, const std::string& path) {
  plot::Figure fig;
  fig.title = "Total diffuse reflectance: relative error against Monte Carlo";
  fig.x_label = "case number (as in the tables)";
  fig.y_label = "(R_d - R_d MC) / R_d MC [%]";
  plot::Series zero;
  zero.label = "0";
  zero.x = {0.0, static_cast<double>(run.cases.size() + 1)};
  zero.y = {0.0, 0.0};
  zero.rgb = {0.6, 0.6, 0.6};
  zero.dashed = true;
  fig.series.push_back(zero);
  double lo = 0, hi = 0;
  for (std::size_t k = 0; k < run.solver_names.size(); ++k) {
    plot::Series s;
    s.label = run.solver_names[k];
    s.markers = true;
    s.rgb = kColours[k % 4];
    for (std::size_t i = 0; i < run.cases.size(); ++i) {
      s.x.push_back(static_cast<double>(i + 1));
      s.y.push_back(100.0 * run.cases[i].relative_error(k));
    }
    fig.series.push_back(s);
    for (double y : s.y) {
      lo = std::min(lo, y);
      hi = std::max(hi, y);
    }
  }
  const double pad = 0.06 * (hi - lo);
  fig.y_min = lo - pad;
  fig.y_max = hi + pad;
  plot::save(fig, path);
}

}  // namespace

std::size_t write_validation_report(std::ostream& md, const ValidationRun& run,
                                    const std::string& plot_dir, const std::string& link_prefix) {
  std::size_t plots = 0;
  const auto& names = run.solver_names;
  const std::size_t ns = names.size();
  md << "# Validation: the transport models against a Monte Carlo reference\n\n";
  md << "Generated by `skin validate` (runs: `skin::mc::run_validation`; report: "
        "src/app/report_validation.cpp). Every case is one Monte Carlo run of "
     << run.mc.photons << " photon packets (seed " << run.mc.seed
     << ") and the same stack through each model; total time " << fmt("%.0f", run.seconds)
     << " s.\n\n";
  md << "The Monte Carlo solver (`skin mc`) follows MCML (Wang, Jacques & Zheng 1995): pencil "
        "beam at normal incidence, Henyey-Greenstein scattering with the layer's g (sigma_s = "
        "sigma_s' / (1 - g)), exact Fresnel reflection and refraction at every interface, Russian "
        "roulette. It reproduces the published benchmark values (tests/mc). All reflectances are "
        "per power that entered the medium (specular reflection excluded), as the diffusion "
        "models define them. R(r) from Monte Carlo is the mean over an annulus, plotted at its "
        "centre; +- is one standard error. Lengths in mm, coefficients in 1/mm.\n\n";

  // Summary by regime.
  md << "## Summary\n\n";
  for (std::size_t k = 0; k < ns; ++k) {
    double worst_in = 0, worst_out = 0;
    std::string case_in, case_out;
    int n_in = 0;
    for (const auto& c : run.cases) {
      const double e = std::abs(c.relative_error(k));
      if (c.c.diffusion_regime) {
        ++n_in;
        if (e >= worst_in) { worst_in = e; case_in = c.c.id; }
      } else if (e >= worst_out) {
        worst_out = e;
        case_out = c.c.id;
      }
    }
    md << "- **" << names[k] << "**: ";
    if (n_in > 0)
      md << "in the diffusion regime (thick, alpha' >= 0.99; " << n_in << " cases) the largest "
         << "|R_d error| is " << fmt("%.2f %%", 100 * worst_in) << " (" << case_in << "); ";
    md << "elsewhere it reaches " << fmt("%.2f %%", 100 * worst_out) << " (" << case_out
       << ").";
    // Profiles in the regime, away from the entry point.
    double worst_profile = 0;
    std::string case_profile;
    for (const auto& c : run.cases) {
      if (!c.c.diffusion_regime || c.R[k].empty()) continue;
      const double e = c.max_profile_error(k, c.top_mfp()).first;
      if (e >= worst_profile) {
        worst_profile = e;
        case_profile = c.c.id;
      }
    }
    if (!case_profile.empty())
      md << " Its R(r) in the diffusion regime, beyond one transport mean free path of the entry "
            "point, is within " << fmt("%.1f %%", 100 * worst_profile) << " (" << case_profile
         << ").";
    // Skin presets: bright and dark.
    double skin_lo = 1e300, skin_hi = 0;
    for (const auto& c : run.cases) {
      if (c.c.group.rfind("Skin", 0) != 0) continue;
      const double e = std::abs(c.relative_error(k));
      skin_lo = std::min(skin_lo, e);
      skin_hi = std::max(skin_hi, e);
    }
    if (skin_hi > 0)
      md << " Over the skin presets |R_d error| ranges from " << fmt("%.1f %%", 100 * skin_lo)
         << " to " << fmt("%.0f %%", 100 * skin_hi) << ".";
    md << "\n";
  }
  md << "\n";
  md << "How to read these numbers:\n\n"
        "- *Thick, high-albedo media* (alpha' >= 0.99, several transport mean free paths) are "
        "where diffusion is derived to hold; the agreement there checks both codes.\n"
        "- *Strong absorption* (alpha' well below 0.95: dark epidermis, blue light) breaks "
        "diffusion: light returns after few scattering events, and with forward scattering "
        "(g = 0.9) it returns less than the isotropic, similarity-scaled picture of diffusion "
        "predicts, so diffusion overestimates R_d, by a factor of 2-4 for the darkest cases. "
        "In that regime R_d also depends on g itself, not only on sigma_s' = sigma_s (1 - g), "
        "which diffusion cannot express.\n"
        "- *Thin layers* (thickness below ~1 transport mean free path, so that the multipole's "
        "source depth z_r = 1 / sigma_t' lies near or beyond the bottom of the layer): the "
        "multipole transmittance of such a layer can be badly wrong, even negative (`skin "
        "layers` warns), and the stack's reflectance with it (case thin-top-over-bright). The "
        "DJ06 epidermis (0.25 mm) is about 1-3 transport mean free paths thick at 400-700 nm.\n"
        "- *Near the entry point* (r below about one transport mean free path) diffusion "
        "misses single and low-order scattering; both errors columns below show it.\n";
  // The profile shape under a matched and a mismatched boundary, when both cases were run.
  const CaseResult* matched = nullptr;
  const CaseResult* mismatched = nullptr;
  for (const auto& c : run.cases) {
    if (c.c.id == "semi-matched-a0.99") matched = &c;
    if (c.c.id == "semi-n1.4-a0.99") mismatched = &c;
  }
  if (matched && mismatched && ns > 0 && !matched->R[0].empty()) {
    md << "- *Profile shape at a mismatched boundary*: the DJ05 R(r) is the diffusive flux "
          "-D dphi/dz at the surface alone; the light that escapes through a mismatched boundary "
          "also carries a part proportional to the fluence there (Kienle & Patterson 1997). "
          "Where R_d agrees to about 1 %, the "
       << names[0] << " R(r) beyond one transport mean free path is off by up to "
       << profile_error_text(*matched, 0, matched->top_mfp()) << " with a matched boundary "
       << "(semi-matched-a0.99) and " << profile_error_text(*mismatched, 0, mismatched->top_mfp())
       << " under air with n = 1.4 (semi-n1.4-a0.99): total reflectance is right, its radial "
          "distribution less so.\n";
  }
  md << "\n";

  // Largest errors.
  // The profile check over the skin presets.
  {
    md << "## Radial profiles of the skin presets, 0.1-5 mm\n\n"
          "Annuli (0.05 mm wide) with centre in 0.1-5 mm whose Monte Carlo estimate has a relative "
          "standard error below 5 %: how many, how many are off by more than 10 % + 3 standard "
          "errors (the goal: none), and the largest excess over 3 standard errors.\n\n";
    check_table_header(md, names, "beyond 10 %", "largest excess (at r)");
    for (const auto& c : run.cases) {
      if (c.c.group.rfind("Skin presets", 0) != 0) continue;
      md << "| " << c.c.id << " | " << c.check_profile(0, 0.1, 5.0, 0.1).checked << " |";
      for (std::size_t k = 0; k < ns; ++k) {
        if (c.R[k].empty()) {
          md << " n/a | n/a |";
          continue;
        }
        const auto pc = c.check_profile(k, 0.1, 5.0, 0.1);
        md << ' ' << pc.beyond << " | "
           << (pc.worst > 0 ? fmt("%.1f %%", 100.0 * pc.worst) + " (" + fmt("%.3g", pc.worst_r) + " mm)"
                            : std::string("within 3 SE"))
           << " |";
      }
      md << '\n';
    }
    md << '\n';
  }

  // The criterion of issue 15 over every case.
  {
    md << "## Radial profiles of every case, 0.02 mm to the outer radius\n\n"
          "The criterion of issue 15 (docs/accurate-solver.md, section 6): over the annuli within "
          "0.02 mm and the case's outer radius (10 mm at most) where the Monte Carlo R(r) is above "
          "1e-6 of its peak, how many are off by more than 5 % + 3 standard errors (the goal: "
          "none), and the largest relative deviation (at r; beyond a few mm it is mostly Monte "
          "Carlo noise, several per cent per annulus). The annuli are those of the Monte Carlo run "
          "(200 to the outer radius: 0.02-0.1 mm wide), the models averaged over each.\n\n";
    check_table_header(md, names, "beyond", "worst (at r)");
    std::vector<int> passed(ns, 0);
    for (const auto& c : run.cases) {
      const double r_hi = std::min(10.0, c.c.r_max);
      md << "| " << c.c.id << " | " << c.check_annuli(0, 0.02, r_hi, 0.05, 1e-6).checked << " |";
      for (std::size_t k = 0; k < ns; ++k) {
        if (c.R[k].empty()) {
          md << " n/a | n/a |";
          continue;
        }
        const auto pc = c.check_annuli(k, 0.02, r_hi, 0.05, 1e-6);
        passed[k] += pc.beyond == 0;
        md << ' ' << pc.beyond << " | " << fmt("%+.1f %%", 100.0 * pc.worst) << " ("
           << fmt("%.3g", pc.worst_r) << " mm) |";
      }
      md << '\n';
    }
    md << "\nCases with no annulus beyond 5 % + 3 SE:";
    for (std::size_t k = 0; k < ns; ++k)
      md << (k ? ", " : " ") << names[k] << ' ' << passed[k] << " of " << run.cases.size();
    md << ".\n\n";
  }

  md << "## Where the errors are largest\n\n";
  for (std::size_t k = 0; k < ns; ++k) {
    std::vector<const CaseResult*> sorted;
    for (const auto& c : run.cases) sorted.push_back(&c);
    std::sort(sorted.begin(), sorted.end(), [k](const CaseResult* a, const CaseResult* b) {
      return std::abs(a->relative_error(k)) > std::abs(b->relative_error(k));
    });
    md << "**" << names[k] << "**, cases by |R_d error| (largest first):\n\n";
    md << "| case | R_d error | max R(r) error at r >= 1 mfp (at r) | max R(r) error, all r | "
          "top layer alpha' | top layer thickness / mfp |\n";
    md << "|---|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < std::min<std::size_t>(10, sorted.size()); ++i) {
      const CaseResult& c = *sorted[i];
      const Layer& top = c.c.stack.layers.front();
      md << "| " << c.c.id << " | " << percent(c.relative_error(k)) << " | "
         << profile_error_text(c, k, c.top_mfp()) << " | " << profile_error_text(c, k, 0.0)
         << " | " << fmt("%.3f", top.sigma_s_prime / (top.sigma_a + top.sigma_s_prime)) << " | "
         << (top.semi_infinite() ? std::string("inf") : fmt("%.2f", top.thickness / mfp(top)))
         << " |\n";
    }
    md << "\n";
  }
  md << "Profile errors are over the annuli where the Monte Carlo estimate has a relative "
        "standard error below 5 %. Diffusion is least accurate within about one transport mean "
        "free path of the entry point (single and low-order scattering, not modelled by a "
        "point source at depth z_r), and in thin or strongly absorbing top layers (dark skin, blue "
        "light: sigma_a comparable to sigma_s'). \"n/a\": no annulus has a Monte Carlo estimate "
        "precise to 5 % (low reflectance).\n\n";

  if (!plot_dir.empty()) {
    plot_overview(run, plot_dir + "/rd_relative_error.png");
    md << "![R_d errors](" << link_prefix << "rd_relative_error.png)\n\n";
    ++plots;
  }

  // Tables by group, in order of first appearance.
  std::vector<std::string> groups;
  for (const auto& c : run.cases)
    if (std::find(groups.begin(), groups.end(), c.c.group) == groups.end())
      groups.push_back(c.c.group);
  md << "## Total diffuse reflectance\n\n";
  for (const auto& g : groups) {
    md << "### " << g << "\n\n| # | case | Monte Carlo R_d | T_d (MC) |";
    for (const auto& n : names) md << " " << n << " R_d | error |";
    md << " diffusion regime |\n|---|---|---|---|";
    for (std::size_t k = 0; k < ns; ++k) md << "---|---|";
    md << "---|\n";
    for (std::size_t i = 0; i < run.cases.size(); ++i) {
      const CaseResult& c = run.cases[i];
      if (c.c.group != g) continue;
      md << "| " << i + 1 << " | " << c.c.id << " | " << fmt("%.5f", c.mc.R_d) << " +- "
         << fmt("%.5f", c.mc.R_d_se) << " | "
         << (c.c.stack.semi_infinite() ? std::string("-") : fmt("%.5f", c.mc.T_d)) << " |";
      for (std::size_t k = 0; k < ns; ++k)
        md << " " << fmt("%.5f", c.R_d[k]) << " | " << percent(c.relative_error(k)) << " |";
      md << " " << (c.c.diffusion_regime ? "yes" : "") << " |\n";
    }
    md << "\n";
  }
  md << "Monte Carlo T_d includes the unscattered (ballistic) transmission.\n\n";

  md << "## Radial profiles\n\n";
  for (const auto& g : groups) {
    md << "### " << g << "\n\n";
    for (const auto& c : run.cases) {
      if (c.c.group != g) continue;
      md << "**" << c.c.id << "**: " << c.c.title << "  \n`" << stack_summary(c.c.stack) << "`";
      for (std::size_t k = 0; k < ns; ++k) {
        if (c.R[k].empty()) continue;
        md << "  \n" << names[k] << ": R_d error " << percent(c.relative_error(k))
           << "; max |R(r) error| at r >= 1 mfp (" << fmt("%.3g mm", c.top_mfp())
           << "): " << profile_error_text(c, k, c.top_mfp())
           << "; over all r: " << profile_error_text(c, k, 0.0);
      }
      md << "\n\n";
      if (!plot_dir.empty()) {
        const std::string file = "profile_" + c.c.id + ".png";
        if (plot_case(c, names, plot_dir + "/" + file)) {
          md << "![" << c.c.id << "](" << link_prefix << file << ")\n\n";
          ++plots;
        } else {
          md << "(No profile plot: no annulus has a Monte Carlo estimate with a relative standard "
                "error below 30 %.)\n\n";
        }
      }
    }
  }
  return plots;
}

namespace {

// A case's worst error over what the check allows: the largest of its annuli's |R - MC| / (5 % +
// 3 SE) and of |R_d - MC| / (0.5 % + 3 SE); it passes where this is at most 1.
double worst_share(const CaseResult& c, std::size_t solver) {
  return std::max(c.check_domain(solver).worst_share, c.rd_share(solver));
}

// One map of the skin domain: every case a marker at (x, y) of its parameters, coloured by its
// worst error over the allowance (worst_share): up to 1/4, 1/2, 1 (passes) or beyond (fails).
void plot_domain_map(const ValidationRun& run, std::size_t solver, const std::string& title,
                     const std::string& x_label, const std::string& y_label, bool log_x,
                     double (*x)(const mc::ValidationCase&), double (*y)(const mc::ValidationCase&),
                     const std::string& path) {
  plot::Figure fig;
  fig.title = title;
  fig.x_label = x_label;
  fig.y_label = y_label;
  fig.log_x = log_x;
  struct Band {
    double upto;
    const char* label;
    std::array<double, 3> rgb;
  };
  const std::array<Band, 4> bands{{{0.25, "worst error <= 1/4 of 5 % + 3 SE", {0.55, 0.8, 0.55}},
                                   {0.5, "1/4 - 1/2 of it", {0.1, 0.6, 0.2}},
                                   {1.0, "1/2 - 1 of it (passes)", {0.95, 0.6, 0.1}},
                                   {std::numeric_limits<double>::infinity(), "beyond it (fails)", {0.85, 0.1, 0.1}}}};
  std::array<plot::Series, 4> series;
  for (std::size_t b = 0; b < bands.size(); ++b) {
    series[b].label = bands[b].label;
    series[b].rgb = bands[b].rgb;
    series[b].markers = true;
  }
  for (const CaseResult& c : run.cases) {
    const double share = worst_share(c, solver);
    std::size_t b = 0;
    while (b + 1 < bands.size() && !(share <= bands[b].upto)) ++b;  // (NaN: beyond)
    series[b].x.push_back(x(c.c));
    series[b].y.push_back(y(c.c));
  }
  for (const plot::Series& s : series)
    if (!s.x.empty()) fig.series.push_back(s);
  plot::save(fig, path);
}

double thickness(const mc::ValidationCase& c) { return c.parameters->epidermis_thickness; }
double melanin(const mc::ValidationCase& c) { return c.parameters->melanin; }
double anisotropy(const mc::ValidationCase& c) { return c.parameters->g; }
double index(const mc::ValidationCase& c) { return c.parameters->eta; }
double wavelength(const mc::ValidationCase& c) { return c.wavelength; }
double blood(const mc::ValidationCase& c) { return c.parameters->hemoglobin; }

}  // namespace

std::size_t write_domain_report(std::ostream& md, const ValidationRun& run,
                                const std::string& plot_dir, std::uint64_t seed) {
  md << "# The transport models over the skin domain, against Monte Carlo\n\n";
  md << "Generated by `skin validate --domain " << run.cases.size() << " --domain-seed " << seed
     << " --photons " << run.mc.photons << "` (" << fmt("%.0f", run.seconds)
     << " s). Each case is a parameter set drawn from the skin domain (`skin parameters`, column "
        "\"skin domain\": its edges and corners included) at one wavelength, solved by each model "
        "and by the project's Monte Carlo (`skin mc`, MCML's method; annuli of "
     << fmt("%.3g", run.cases.empty() || run.cases[0].mc.r_mm.size() < 2
                        ? 0.0
                        : run.cases[0].mc.r_mm[1] - run.cases[0].mc.r_mm[0])
     << " mm to 10 mm).\n\n"
        "The check (issue 31): every annulus within 0.02-10 mm whose Monte Carlo relative standard "
        "error is below 3 % lies within 5 % + 3 SE, and R_d within 0.5 % + 3 SE.\n\n";
  md << "## Summary\n\n| model | cases passing | annuli checked | annuli beyond | worst deviation "
        "(case, r) | R_d outside 0.5 % + 3 SE |\n|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < run.solver_names.size(); ++k) {
    int pass = 0, checked = 0, beyond = 0, rd_bad = 0;
    double worst = 0;
    std::string where = "-";
    for (const CaseResult& c : run.cases) {
      const auto pc = c.check_domain(k);
      const bool rd = c.rd_within(k);
      checked += pc.checked;
      beyond += pc.beyond;
      rd_bad += rd ? 0 : 1;
      pass += pc.beyond == 0 && rd ? 1 : 0;
      if (std::abs(pc.worst) > std::abs(worst)) {
        worst = pc.worst;
        where = c.c.id + ", " + fmt("%.3g", pc.worst_r) + " mm";
      }
    }
    md << "| " << run.solver_names[k] << " | " << pass << " of " << run.cases.size() << " | "
       << checked << " | " << beyond << " | " << percent(worst) << " (" << where << ") | " << rd_bad
       << " |\n";
  }
  md << "\n";
  // The maps, for the default model (accurate) when it was run, else the first.
  std::size_t main = 0;
  for (std::size_t k = 0; k < run.solver_names.size(); ++k)
    if (run.solver_names[k] == "accurate") main = k;
  if (!plot_dir.empty() && !run.cases.empty()) {
    const std::string& name = run.solver_names[main];
    plot_domain_map(run, main, "Skin domain: " + name + " against Monte Carlo",
                    "epidermis thickness [mm]", "melanin C_m", true, thickness, melanin,
                    plot_dir + "/domain_thickness_melanin.png");
    plot_domain_map(run, main, "Skin domain: " + name + " against Monte Carlo", "g", "index eta",
                    false, anisotropy, index, plot_dir + "/domain_g_eta.png");
    plot_domain_map(run, main, "Skin domain: " + name + " against Monte Carlo", "wavelength [nm]",
                    "melanin C_m", false, wavelength, melanin, plot_dir + "/domain_wavelength_melanin.png");
    plot_domain_map(run, main, "Skin domain: " + name + " against Monte Carlo", "wavelength [nm]",
                    "blood C_h", false, wavelength, blood, plot_dir + "/domain_wavelength_blood.png");
    md << "## Maps of the domain (" << name << ")\n\n"
       << "Each case is a marker at two of its parameters, coloured by its worst error over what the "
          "check allows (the column `worst / allowed` below): up to 1/4, 1/2 or 1 of it (passes), or "
          "beyond (fails).\n\n"
       << "![thickness and melanin](domain_thickness_melanin.png)\n"
          "![g and index](domain_g_eta.png)\n"
          "![wavelength and melanin](domain_wavelength_melanin.png)\n"
          "![wavelength and blood](domain_wavelength_blood.png)\n\n";
  }
  // How the accurate model got each case's profile: read from the skin table or solved.
  const bool accurate = run.solver_names[main] == "accurate";
  std::vector<const char*> route;
  std::size_t read = 0;
  for (const CaseResult& c : run.cases) {
    const bool table = transport::accurate::AccurateStack::reads_table(c.c.stack);
    read += table ? 1 : 0;
    route.push_back(!accurate ? "-" : table ? "table" : "solved");
  }
  md << "## Every case\n\n`worst / allowed`: the case's largest |R - MC| / (5 % + 3 SE) over its annuli "
        "and |R_d - MC| / (0.5 % + 3 SE); it passes where this is at most 1 (the maps' colours).";
  if (accurate)
    md << " `profile`: read from the skin or half-space table or solved in the frequency domain (" << read << " of "
       << run.cases.size() << " read).";
  md << "\n\n| case | parameters | profile | annuli | beyond 5 % + 3 SE | worst (r mm) | worst / allowed | MC R_d | "
     << run.solver_names[main] << " R_d - MC |\n|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < run.cases.size(); ++i) {
    const CaseResult& c = run.cases[i];
    const auto pc = c.check_domain(main);
    md << "| " << c.c.id << " | " << c.c.title << " | " << route[i] << " | "
       << pc.checked << " | " << pc.beyond << " | "
       << percent(pc.worst) << " (" << fmt("%.3g", pc.worst_r) << ") | " << fmt("%.2f", worst_share(c, main))
       << " | " << fmt("%.5g", c.mc.R_d)
       << " +- " << fmt("%.2g", c.mc.R_d_se) << " | "
       << fmt("%+.2f SE", (c.R_d[main] - c.mc.R_d) / std::max(c.mc.R_d_se, 1e-300)) << " |\n";
  }
  return run.cases.size();
}

std::string validation_case_line(const CaseResult& c,
                                 const std::vector<std::string>& solver_names) {
  std::string line =
      c.c.id + ": MC R_d " + fmt("%.5f", c.mc.R_d) + " +- " + fmt("%.5f", c.mc.R_d_se);
  for (std::size_t k = 0; k < solver_names.size(); ++k)
    line += ", " + solver_names[k] + " " + fmt("%.5f", c.R_d[k]) + " (" +
            percent(c.relative_error(k)) + ")";
  return line + ", " + fmt("%.1f s", c.mc.seconds);
}

}  // namespace skin::cli
