#pragma once
// Diffusion (and any other solver) against the Monte Carlo reference, over the paper's skin
// presets and generic layer stacks: the cases, their runs and the error measures. The library
// computes and returns them; the application writes the report (Markdown, plots:
// src/app/report_validation.cpp).
//
// Solvers are columns: each is a name and two callables (LayerStack -> R_d, and
// LayerStack, radii -> R(r)), so another model (for example a more accurate transport solver)
// is compared by appending a SolverColumn; the report's tables, plots and error summary grow a
// column, a curve and a line for it.
#include <cstdint>
#include <functional>
#include <optional>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "skin/mc/mc.hpp"
#include "skin/physics/layer.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/transport/model.hpp"

namespace skin::mc {

struct SolverColumn {
  std::string name;  // column header, e.g. "multipole"
  // Total diffuse reflectance per power that entered.
  std::function<double(const physics::LayerStack&)> R_d;
  // R(r) per power that entered [1/mm^2] at the radii given [mm]; empty function = no profile.
  std::function<std::vector<double>(const physics::LayerStack&, const std::vector<double>& r_mm)> profile;
};
// A transport model of the registry (its R_d, and R(r) by skin::transport::ProfileSolver of its response);
// the column is named after the model.
SolverColumn solver_column(const transport::Model& model);

struct ValidationCase {
  std::string id;     // file-name safe: "pale-650nm", "slab-2mfp"
  std::string group;  // section of the report: "Skin presets", "Semi-infinite", ...
  std::string title;  // one line for humans
  physics::LayerStack stack;
  // Thick, high-albedo (alpha' >= 0.99, several transport mean free paths): where diffusion is
  // known to be accurate and the report expects agreement within a few per cent.
  bool diffusion_regime = false;
  double r_max = 10.0;  // outer radius of the profile [mm]
  // For a skin case: its parameters and wavelength [nm] (domain_cases; the report's maps).
  std::optional<physics::SkinParameters> parameters;
  double wavelength = 0;
};
std::ostream& operator<<(std::ostream& os, const ValidationCase& c);

// The paper's presets (caucasian, asian, african, pale, tanned, ear) at each wavelength [nm].
std::vector<ValidationCase> preset_cases(const std::vector<double>& wavelengths);
// Generic stacks: semi-infinite (matched and mismatched, several albedos), slabs of 0.5-20
// transport mean free paths, bright-over-dark and dark-over-bright pairs, mismatched indices.
std::vector<ValidationCase> generic_cases();

// `n` skin cases drawn from the skin domain (sample_skin_domain(n, seed), skin_parameters.hpp),
// each at one wavelength: a quarter in 400-480 nm (dark skin's far field in the blue), one in
// sixteen at 380 nm and at 780 nm, the rest uniform over 380-780 nm. Outer radius 10 mm.
std::vector<ValidationCase> domain_cases(std::size_t n, std::uint64_t seed);

struct CaseResult {
  ValidationCase c;
  Result mc;
  std::vector<double> R_d;             // per solver
  // Per solver: R(r) averaged over the same annuli as the Monte Carlo bins (so that the two are
  // compared like for like near r = 0, where R changes fast); empty: solver has no profile.
  std::vector<std::vector<double>> R;
  // Per solver: R(r) at the radii r_fine (log-spaced, for the plots).
  std::vector<double> r_fine;
  std::vector<std::vector<double>> R_fine;
  // (R_d[solver] - mc.R_d) / mc.R_d
  double relative_error(std::size_t solver) const;
  // Largest |R[solver] / mc.R - 1| over the bins at r >= r_min [mm] where the Monte Carlo
  // relative standard error is below 5 %, and the radius of that bin [mm] (NaN, NaN when no bin
  // qualifies).
  std::pair<double, double> max_profile_error(std::size_t solver, double r_min = 0.0) const;
  // The profile check: over the bins with centre in [r_lo, r_hi] [mm] whose Monte Carlo
  // relative standard error is below 5 %, how many there are, how many are off by more than
  // `rel` + 3 standard errors, and the largest excess (|R / mc.R - 1| - 3 SE / mc.R) with its
  // radius.
  struct ProfileCheck {
    int checked = 0, beyond = 0;
    double worst = 0, worst_r = 0;
    // check_domain: the largest |R - mc.R| over the annulus' allowance (5 % of mc.R + 3 SE):
    // <= 1 where every annulus passes.
    double worst_share = 0;
  };
  ProfileCheck check_profile(std::size_t solver, double r_lo, double r_hi, double rel) const;
  // The criterion of issue 15 (docs/accurate-solver.md, section 6): over the annuli that lie
  // within [r_lo, r_hi] [mm] and whose Monte Carlo R is above `floor` times its largest, how many
  // there are, how many are off by more than `rel` + 3 SE, and the largest relative deviation
  // R / mc.R - 1 (signed, in `worst`) with its radius.
  ProfileCheck check_annuli(std::size_t solver, double r_lo, double r_hi, double rel,
                            double floor) const;
  // The check of the skin domain (issue 31; docs/accurate-solver.md, section 7): over the annuli
  // within 0.02-10 mm whose Monte Carlo relative standard error is below 3 %, how many lie beyond
  // 5 % + 3 SE, the largest relative deviation (signed) and its radius.
  ProfileCheck check_domain(std::size_t solver) const;
  // Whether R_d lies within 0.5 % + 3 standard errors of the Monte Carlo's, and |R_d - mc.R_d|
  // over that allowance.
  bool rd_within(std::size_t solver, double rel = 0.005) const;
  double rd_share(std::size_t solver, double rel = 0.005) const;
  // Transport mean free path 1 / sigma_t' of the top layer [mm].
  double top_mfp() const;
};

struct ValidationRun {
  std::vector<std::string> solver_names;
  std::vector<CaseResult> cases;
  Options mc;  // photons, seed of every case (r_max per case)
  double seconds = 0;
};

// Progress of run_validation: called after each case, from the calling thread, with the cases
// done, the cases in total and the result of the case just finished.
using CaseDone =
    std::function<void(std::size_t done, std::size_t total, const CaseResult& result)>;

// Runs every case through the Monte Carlo solver (options.photons per case, options.seed; its
// r_max replaced by the case's) and every solver. `on_case` may be empty.
ValidationRun run_validation(const std::vector<ValidationCase>& cases,
                             const std::vector<SolverColumn>& solvers, const Options& options,
                             const CaseDone& on_case = {});

}  // namespace skin::mc
