// Diffusion vs Monte Carlo: the cases and their runs (see validation.hpp); the report is the
// application's (src/app/report_validation.cpp).
#include "skin/mc/validation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>

#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"
#include "skin/util/random.hpp"
#include "skin/transport/profile.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/transport/stack.hpp"

namespace skin::mc {

using skin::util::InputError;
using skin::util::splitmix64;

using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::Preset;
using skin::physics::SkinParameters;
using skin::physics::find_preset;
using skin::physics::kInfinity;
using skin::physics::sample_skin_domain;
using skin::physics::skin_layer_stack;

namespace {

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace

std::ostream& operator<<(std::ostream& os, const ValidationCase& c) {
  return os << "ValidationCase{" << c.id << ", " << c.group << ", " << c.stack
            << ", diffusion_regime=" << c.diffusion_regime << ", r_max=" << c.r_max << "mm}";
}

SolverColumn solver_column(const transport::Model& model) {
  SolverColumn s;
  s.name = std::string(model.name());
  s.R_d = [&model](const LayerStack& stack) { return model.R_d(stack); };
  s.profile = [&model](const LayerStack& stack, const std::vector<double>& r) {
    ProfileSolver solver(RadialGrid::from(r));
    return solver.profile(*model.response(stack));
  };
  return s;
}

std::vector<ValidationCase> preset_cases(const std::vector<double>& wavelengths) {
  std::vector<ValidationCase> cases;
  for (const char* name : {"caucasian", "asian", "african", "pale", "tanned", "ear"}) {
    const Preset& p = find_preset(name);
    for (double lambda : wavelengths) {
      ValidationCase c;
      c.id = std::string(name) + "-" + fmt("%.0f", lambda) + "nm";
      c.group = "Skin presets (DJ06 two-layer model)";
      c.title = std::string(name) + " at " + fmt("%.0f", lambda) + " nm";
      c.stack = skin_layer_stack(p.parameters, lambda);
      // Profiles are short in the blue (strong absorption) and long in the red.
      c.r_max = lambda < 500 ? 4.0 : (lambda < 600 ? 6.0 : 10.0);
      cases.push_back(c);
    }
  }
  return cases;
}

std::vector<ValidationCase> domain_cases(std::size_t n, std::uint64_t seed) {
  const std::vector<SkinParameters> sets = sample_skin_domain(n, seed);
  // The wavelengths from their own sequence (splitmix64, as sample_skin_domain), so that the
  // parameter sets are those of sample_skin_domain(n, seed).
  std::uint64_t state = seed ^ 0x5bd1e9955bd1e995ULL;
  auto uniform = [&state] { return static_cast<double>(splitmix64(state) >> 11) * 0x1.0p-53; };
  std::vector<ValidationCase> cases;
  for (std::size_t i = 0; i < n; ++i) {
    const double pick = uniform(), u = uniform();
    const double lambda = pick < 0.25 ? 400 + 80 * u
                          : pick < 0.3125 ? 380.0
                          : pick < 0.375 ? 780.0
                                         : 380 + 400 * u;
    const double l = std::round(lambda);
    const SkinParameters& p = sets[i];
    p.validate();  // a draw the model would refuse is not skin (skin_layer_stack does not check)
    ValidationCase c;
    c.id = "domain-" + std::to_string(i + 1) + "-" + fmt("%.0f", l) + "nm";
    c.group = "Skin domain (seed " + std::to_string(seed) + ")";
    c.title = "C_m " + fmt("%.3g", p.melanin) + ", beta_m " + fmt("%.2g", p.melanin_blend) + ", C_h " +
              fmt("%.3g", p.hemoglobin) + ", d " + fmt("%.3g", p.epidermis_thickness) + " mm, g " +
              fmt("%.3g", p.g) + ", n " + fmt("%.3g", p.eta) + ", dermis " +
              fmt("%.2g", p.dermis_scattering_scale) + ", scale " + fmt("%.2g", p.scattering_scale) +
              " at " + fmt("%.0f", l) + " nm";
    c.stack = skin_layer_stack(p, l);
    c.r_max = 10.0;
    c.parameters = p;
    c.wavelength = l;
    cases.push_back(std::move(c));
  }
  return cases;
}

std::vector<ValidationCase> generic_cases() {
  std::vector<ValidationCase> cases;
  auto add = [&](std::string id, std::string group, std::string title, LayerStack s, bool regime,
                 double r_max) {
    cases.push_back({std::move(id), std::move(group), std::move(title), std::move(s), regime, r_max, std::nullopt, 0.0});
  };
  const double g = 0.9;
  // Semi-infinite, sigma_t' = 1/mm (transport mean free path 1 mm).
  {
    LayerStack s;
    s.layers = {{0.01, 0.99, kInfinity, 1.0, g}};
    add("semi-matched-a0.99", "Semi-infinite", "alpha' = 0.99, matched boundary (n = 1)", s, true, 20);
    s.layers = {{0.01, 0.99, kInfinity, 1.4, g}};
    add("semi-n1.4-a0.99", "Semi-infinite", "alpha' = 0.99, n = 1.4 under air", s, true, 20);
    s.layers = {{0.05, 0.95, kInfinity, 1.4, g}};
    add("semi-n1.4-a0.95", "Semi-infinite", "alpha' = 0.95, n = 1.4 under air", s, false, 10);
    s.layers = {{0.2, 0.8, kInfinity, 1.4, g}};
    add("semi-n1.4-a0.8", "Semi-infinite", "alpha' = 0.8, n = 1.4 under air", s, false, 6);
    s.layers = {{0.5, 0.5, kInfinity, 1.4, g}};
    add("semi-n1.4-a0.5", "Semi-infinite", "alpha' = 0.5, n = 1.4 under air (sigma_a = sigma_s')", s,
        false, 4);
  }
  // Slabs in air, alpha' = 0.99, thickness in transport mean free paths (1 mm).
  for (double d : {0.5, 2.0, 5.0, 20.0}) {
    LayerStack s;
    s.layers = {{0.01, 0.99, d, 1.4, g}};
    add("slab-" + fmt("%g", d) + "mfp", "Slabs in air",
        "alpha' = 0.99, n = 1.4, thickness " + fmt("%g", d) + " transport mfp", s, d >= 20.0, 20);
  }
  // Two layers.
  {
    LayerStack s;
    s.layers = {{0.01, 2.0, 1.0, 1.4, g}, {0.3, 1.0, kInfinity, 1.4, g}};
    add("bright-over-dark", "Two layers",
        "bright top (alpha' 0.995, 2 mfp thick) over dark semi-infinite (alpha' 0.77)", s, false, 10);
    s.layers = {{0.3, 4.0, 0.5, 1.4, g}, {0.01, 1.0, kInfinity, 1.4, g}};
    add("dark-over-bright", "Two layers",
        "dark top (alpha' 0.93, 2.2 mfp thick) over bright semi-infinite (alpha' 0.99)", s, false, 20);
    s.layers = {{0.3, 2.0, 0.2, 1.4, g}, {0.01, 1.0, kInfinity, 1.4, g}};
    add("thin-top-over-bright", "Two layers",
        "thin dark top (alpha' 0.87, 0.46 mfp thick: z_r = 0.43 mm > d = 0.2 mm) over bright "
        "semi-infinite (alpha' 0.99)", s, false, 20);
    s.layers = {{0.02, 1.5, 1.5, 1.33, g}, {0.02, 1.0, kInfinity, 1.55, g}};
    add("mismatched-1.33-1.55", "Two layers",
        "n = 1.33 top (2.3 mfp) over n = 1.55 semi-infinite, both alpha' ~0.98", s, false, 15);
  }
  // Mismatched below: a slab on glass.
  {
    LayerStack s;
    s.layers = {{0.02, 1.0, 2.0, 1.4, g}};
    s.eta_below = 1.5;
    add("slab-on-glass", "Slabs in air", "alpha' = 0.98, n = 1.4, 2 mfp thick, n = 1.5 below", s,
        false, 15);
  }
  return cases;
}

double CaseResult::relative_error(std::size_t solver) const {
  return (R_d.at(solver) - mc.R_d) / mc.R_d;
}

std::pair<double, double> CaseResult::max_profile_error(std::size_t solver, double r_min) const {
  const auto& P = R.at(solver);
  double worst = std::numeric_limits<double>::quiet_NaN(), at = worst;
  for (std::size_t i = 0; i < P.size() && i < mc.R.size(); ++i) {
    if (mc.r_mm[i] < r_min || !(mc.R[i] > 0) || mc.R_se[i] > 0.05 * mc.R[i]) continue;
    const double e = std::abs(P[i] / mc.R[i] - 1.0);
    if (!(e <= worst)) {
      worst = e;
      at = mc.r_mm[i];
    }
  }
  return {worst, at};
}

CaseResult::ProfileCheck CaseResult::check_profile(std::size_t solver, double r_lo, double r_hi,
                                                   double rel) const {
  ProfileCheck pc;
  const auto& P = R.at(solver);
  for (std::size_t i = 0; i < P.size() && i < mc.R.size(); ++i) {
    const double r = mc.r_mm[i];
    if (r < r_lo || r > r_hi || !(mc.R[i] > 0) || mc.R_se[i] > 0.05 * mc.R[i]) continue;
    ++pc.checked;
    const double excess = (std::abs(P[i] - mc.R[i]) - 3.0 * mc.R_se[i]) / mc.R[i];
    if (excess > rel) ++pc.beyond;
    if (excess > pc.worst) {
      pc.worst = excess;
      pc.worst_r = r;
    }
  }
  return pc;
}

CaseResult::ProfileCheck CaseResult::check_annuli(std::size_t solver, double r_lo, double r_hi,
                                                  double rel, double floor) const {
  ProfileCheck pc;
  const auto& P = R.at(solver);
  if (mc.r_mm.empty()) return pc;
  const double half = 0.5 * (mc.r_mm.size() > 1 ? mc.r_mm[1] - mc.r_mm[0] : 2 * mc.r_mm[0]);
  const double peak = *std::max_element(mc.R.begin(), mc.R.end());
  for (std::size_t i = 0; i < P.size() && i < mc.R.size(); ++i) {
    const double r = mc.r_mm[i];
    if (r - half < r_lo - 1e-12 || r + half > r_hi + 1e-9 || !(mc.R[i] > floor * peak)) continue;
    ++pc.checked;
    const double dev = P[i] / mc.R[i] - 1.0;
    if (std::abs(P[i] - mc.R[i]) > rel * mc.R[i] + 3.0 * mc.R_se[i]) ++pc.beyond;
    if (std::abs(dev) > std::abs(pc.worst)) {
      pc.worst = dev;
      pc.worst_r = r;
    }
  }
  return pc;
}

CaseResult::ProfileCheck CaseResult::check_domain(std::size_t solver) const {
  ProfileCheck pc;
  const auto& P = R.at(solver);
  if (mc.r_mm.empty()) return pc;
  const double half = 0.5 * (mc.r_mm.size() > 1 ? mc.r_mm[1] - mc.r_mm[0] : 2 * mc.r_mm[0]);
  for (std::size_t i = 0; i < P.size() && i < mc.R.size(); ++i) {
    const double r = mc.r_mm[i];
    if (r - half < 0.02 - 1e-12 || r + half > 10.0 + 1e-9 || !(mc.R_se[i] < 0.03 * mc.R[i])) continue;
    ++pc.checked;
    const double dev = P[i] / mc.R[i] - 1.0;
    const double allowed = 0.05 * mc.R[i] + 3.0 * mc.R_se[i];
    if (std::abs(P[i] - mc.R[i]) > allowed) ++pc.beyond;
    pc.worst_share = std::max(pc.worst_share, std::abs(P[i] - mc.R[i]) / allowed);
    if (std::abs(dev) > std::abs(pc.worst)) {
      pc.worst = dev;
      pc.worst_r = r;
    }
  }
  return pc;
}

namespace {
// What the check allows R_d to differ from the Monte Carlo's: rel of it plus 3 standard errors.
double rd_allowance(const Result& mc, double rel) { return rel * mc.R_d + 3.0 * mc.R_d_se; }
}  // namespace

bool CaseResult::rd_within(std::size_t solver, double rel) const {
  return std::abs(R_d.at(solver) - mc.R_d) <= rd_allowance(mc, rel);
}

double CaseResult::rd_share(std::size_t solver, double rel) const {
  return std::abs(R_d.at(solver) - mc.R_d) / rd_allowance(mc, rel);
}

double CaseResult::top_mfp() const {
  const Layer& l = c.stack.layers.front();
  return 1.0 / (l.sigma_a + l.sigma_s_prime);
}

namespace {

std::vector<double> log_radii(double r_min, double r_max, std::size_t n) {
  std::vector<double> r(n);
  for (std::size_t i = 0; i < n; ++i)
    r[i] = r_min * std::pow(r_max / r_min, static_cast<double>(i) / static_cast<double>(n - 1));
  return r;
}

// Mean of R over each annulus [r_i - dr/2, r_i + dr/2] (centres r_i evenly spaced from dr/2):
// 3-point Gauss-Legendre in the area variable s = r^2, exact for R quadratic in r^2; and R at the
// radii `fine`, from the same call of the solver (one response per stack: the frequency-domain
// models take seconds to build one).
std::pair<std::vector<double>, std::vector<double>> annulus_means(
    const SolverColumn& s, const LayerStack& stack, const std::vector<double>& centres,
    const std::vector<double>& fine) {
  const double dr = 2.0 * centres.front();
  static const double x[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
  static const double w[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};  // weights / 2: sum to 1
  std::vector<double> radii;
  radii.reserve(3 * centres.size());
  for (double c : centres) {
    const double a = (c - 0.5 * dr) * (c - 0.5 * dr), b = (c + 0.5 * dr) * (c + 0.5 * dr);
    for (double xi : x) radii.push_back(std::sqrt(0.5 * (a + b) + 0.5 * (b - a) * xi));
  }
  radii.insert(radii.end(), fine.begin(), fine.end());
  // The solver takes increasing radii: solve at the sorted, distinct ones and look each up.
  std::vector<double> sorted = radii;
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  const std::vector<double> u = s.profile(stack, sorted);
  std::vector<double> v(radii.size());
  for (std::size_t i = 0; i < radii.size(); ++i)
    v[i] = u[static_cast<std::size_t>(std::lower_bound(sorted.begin(), sorted.end(), radii[i]) - sorted.begin())];
  std::vector<double> mean(centres.size());
  for (std::size_t i = 0; i < centres.size(); ++i)
    mean[i] = w[0] * v[3 * i] + w[1] * v[3 * i + 1] + w[2] * v[3 * i + 2];
  return {std::move(mean), std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(3 * centres.size()), v.end())};
}

}  // namespace

ValidationRun run_validation(const std::vector<ValidationCase>& cases,
                             const std::vector<SolverColumn>& solvers, const Options& options,
                             const CaseDone& on_case) {
  const auto t0 = std::chrono::steady_clock::now();
  ValidationRun run;
  run.mc = options;
  for (const auto& s : solvers) {
    if (!s.R_d) throw InputError("solver '" + s.name + "' has no R_d function");
    run.solver_names.push_back(s.name);
  }
  for (const auto& c : cases) {
    CaseResult cr;
    cr.c = c;
    Options o = options;
    o.r_max = c.r_max;
    cr.mc = simulate(c.stack, o);
    cr.r_fine = log_radii(0.5 * cr.mc.r_mm.front(), c.r_max, 200);
    for (const auto& s : solvers) {
      util::cancel::check();
      cr.R_d.push_back(s.R_d(c.stack));
      if (s.profile) {
        auto [means, fine] = annulus_means(s, c.stack, cr.mc.r_mm, cr.r_fine);
        cr.R.push_back(std::move(means));
        cr.R_fine.push_back(std::move(fine));
      } else {
        cr.R.emplace_back();
        cr.R_fine.emplace_back();
      }
    }
    run.cases.push_back(std::move(cr));
    if (on_case) on_case(run.cases.size(), cases.size(), run.cases.back());
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

}  // namespace skin::mc
