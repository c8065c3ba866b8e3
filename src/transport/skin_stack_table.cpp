#include "skin/transport/skin_stack_table.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <sstream>
#include <tuple>

#include "skin/transport/accurate.hpp"
#include "skin/transport/profile.hpp"
#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"
#include "skin/util/interpolation.hpp"
#include "skin/util/table.hpp"
#include "ad_core.hpp"
#include "skin_tables_core.hpp"

namespace skin::transport::accurate {

using skin::util::InputError;
using skin::util::Lagrange4Stencil;
using skin::util::ProgressCallback;
using skin::util::Table;
using skin::util::csv_metadata;
using skin::util::format_number;
using skin::util::format_number_list;
using skin::util::lagrange4_stencil;
using skin::util::lagrange4_weights;
using skin::util::metadata_number;
using skin::util::metadata_numbers;
using skin::util::parse_csv;

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::kInfinity;

namespace tables {

double clamp_ln(double v) {
  constexpr double lim = kMaxLnRho + kOvershoot;
  return std::isnan(v) ? -lim : std::clamp(v, -lim, lim);
}

std::vector<double> floored_log(std::vector<double> R) {
  const double peak = *std::max_element(R.begin(), R.end());
  for (double& v : R) v = std::log(std::max(v, kFloor * peak));
  return R;
}

std::vector<double> mapped(const std::vector<double>& v, double (*f)(double)) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = f(v[i]);
  return out;
}
double log_of(double v) { return std::log(v); }
double sqrt_of(double v) { return std::sqrt(v); }

void check_x_nodes(const std::vector<double>& x, const std::string& src) {
  const double h = std::log(x.back() / x.front()) / static_cast<double>(x.size() - 1);
  for (std::size_t i = 1; i < x.size(); ++i)
    if (x.size() % 2 == 0 || !(std::abs(std::log(x[i] / x[i - 1]) / h - 1) <= 1e-5))
      throw InputError(src + ": 'x' must be an odd number of nodes evenly spaced in ln x");
}

void check_row(const double* out, std::size_t n_x, const std::string& src, std::size_t r,
               const std::vector<std::string>& columns) {
  for (std::size_t i = 0; i < n_x; ++i)
    if (!(std::abs(out[i]) <= kMaxLnRho))
      throw InputError(src + ": row " + std::to_string(r) + ", column " + columns[3 + i] + " = " +
                       format_number(out[i]) + " is not a finite number within " + format_number(kMaxLnRho) +
                       " of 0 (ln rho)");
  const auto [lo, hi] = std::minmax_element(out, out + n_x);
  if (!(*hi - *lo <= kMaxRowSpan))
    throw InputError(src + ": row " + std::to_string(r) + " spans " + format_number(*hi - *lo) +
                     " in ln rho; allowed: at most " + format_number(kMaxRowSpan) +
                     " (the table's floor, 1e-13 of a row's peak)");
}

bool same_node(double a, double b) { return std::abs(a - b) <= 1e-6 * std::abs(b); }
bool same_nodes(const std::vector<double>& a, const std::vector<double>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), same_node);
}

namespace {
// A ProfileSolver on these x nodes, one per thread and kept: its quadratures (the J0 weights of
// the radii for a k_max, which depend on nothing else) are reused from one solve to the next
// instead of being built again for each (a quarter of a thin row's time). The same numbers.
ProfileSolver& solver_on(const std::vector<double>& x) {
  thread_local std::vector<std::pair<std::vector<double>, std::unique_ptr<ProfileSolver>>> solvers;
  for (auto& [nodes, solver] : solvers)
    if (nodes == x) return *solver;
  if (solvers.size() >= 4) solvers.erase(solvers.begin());
  solvers.emplace_back(x, std::make_unique<ProfileSolver>(RadialGrid::from(x)));
  return *solvers.back().second;
}

}  // namespace

// rho at the x nodes of one layer over this lower layer (FrequencyStack; in units of
// s: k0 = 0.3 / 15, the resolution FrequencyStack has on the most scattering skin, 5 % at 10 mm
// otherwise: its nodes are fixed in rad/mm, so in units of s = 1 /mm they would be those of a
// stack with s = 1 /mm, and the skin's s is 4-15 /mm).
std::vector<double> solve(const std::vector<double>& x, double eta, double g, double tau_v, double a_v,
                          const Layer* below) {
  LayerStack st;
  st.eta_above = 1.0;
  st.layers.push_back({a_v, 1.0, tau_v, eta, g});
  if (below) st.layers.push_back(*below);
  FrequencyProfileOptions o;
  o.k0 = 0.3 / 15.0;
  const FrequencyStack f(st, o);
  return solver_on(x).profile(f);
}
}  // namespace tables

using namespace tables;

namespace {

// ln(e^a + e^b)
double log_sum(double a, double b) { return std::max(a, b) + std::log1p(std::exp(-std::abs(a - b))); }

// The offsets and the cross terms stop at a lighter top layer than the table (their a_e nodes end
// at kOffsetsDarkestTop, the table's at 16.06 since 2026-12-06) and beyond their last a_e node hold
// its values (inside, 4-point Lagrange in sqrt a_e as the table). In a dark epidermis the top
// layer's light is mostly scattered once, and at a fixed reduced scattering another g or index
// changes its extinction and phase function by amounts that do not depend on sigma_a: its offset
// varies little with a_e there (measured against the solver: docs/accurate-solver.md, sec. 4).
constexpr double kOffsetsDarkestTop = 6.93;
// How far beyond it the held offsets are read (another g, index or dermis ratio; at the table's
// own geometry the table's nodes, to 16.1): against the solver (above 1e-4 of R(0.02 mm) and 1e-6
// of R(1 um), docs/accurate-solver.md, sec. 4), 34 random domain skins with a_e
// 6.93-12 were median 2.3 %, one beyond 5 % (6.0 %); 14 with a_e 12-16 median 5.8 %, 9 beyond 5 %
// (up to 11 %; 8 of the 9 with g below 0.8): the held offsets' shape drifts from the solver's.
constexpr double kOffsetsHeldReach = 12.0;
// The last node's values (a stencil of the last four nodes, all the weight on the last).
Lagrange4Stencil last_node(std::size_t n) {
  Lagrange4Stencil s;
  s.first = n - 4;
  s.weights = {0, 0, 0, 1};
  return s;
}
Lagrange4Stencil a_e_stencil_held(const std::vector<double>& nodes, double ae) {
  return ae <= nodes.back() ? lagrange4_stencil(mapped(nodes, sqrt_of), std::sqrt(ae)) : last_node(nodes.size());
}
// Likewise in tau beyond kOffsetsThickestTop, the offsets' last tau node (the table's reach
// farther, to 22.8, since 2026-12-06): as tau grows the top layer tends to a half-space, and its
// offsets with it (at tau 4.5, 6.75 and 10.1, on five nodes, within 0.005 of each other out to x = 2.4,
// 0.01-0.09 at x = 13); the light from below, whose offsets still move with tau there, has
// crossed ten transport mean free paths of epidermis twice (docs/accurate-solver.md, sec. 4).
// Inside, in ln tau (the top layer) or tau (the light from below) as the table.
constexpr double kOffsetsThickestTop = 10.13;
Lagrange4Stencil tau_stencil_held(const std::vector<double>& nodes, double t, bool in_log) {
  if (t > nodes.back()) return last_node(nodes.size());
  return in_log ? lagrange4_stencil(mapped(nodes, log_of), std::log(t)) : lagrange4_stencil(nodes, t);
}

}  // namespace

SkinStackTable SkinStackTable::default_nodes() {
  SkinStackTable t;
  // tau 0.078-22.8 (the last two since 2026-12-06, the offsets held beyond 10.1: kOffsetsThickestTop).
  for (int k = -8; k <= 6; ++k) t.tau.push_back(2.0 * std::pow(1.5, k));
  // a: four per decade from 0.00126 to 0.4, then evenly in sqrt(a) (0.25 apart, then 0.5). (The
  // skin domain's least absorbing skin, red light through the thinnest melanin and blood, reaches
  // a_e and a_d 0.0015: the two nodes below 0.004 date from 2026-12-06.)
  std::vector<double> a;
  for (int k = -2; k <= 8; ++k) a.push_back(0.004 * std::pow(10.0, k / 4.0));
  const double u0 = std::sqrt(a.back());
  t.a_e = a;
  for (int j = 1; j <= 8; ++j) a.push_back(std::pow(u0 + 0.25 * j, 2));
  for (int j = 1; j <= 2; ++j) a.push_back(std::pow(u0 + 2.0 + 0.5 * j, 2));
  t.a_d = a;
  // The top layer twice as dense beyond 0.4 (0.125 apart in sqrt a, up to 6.93: every preset at
  // 380-780 nm; up to 16.06 since 2026-12-06, with the offsets held beyond 6.93 and read so up to
  // kOffsetsHeldReach): a dark epidermis' far field is a sum of paths whose attenuation differs by
  // several e-folds between nodes 0.25 apart (90 % off midway at a_e 0.57 with those).
  for (int j = 1; j <= 27; ++j) t.a_e.push_back(std::pow(u0 + 0.125 * j, 2));
  // The half-space: eight per decade from 1e-4 (alpha' 0.9999) to 1, then 0.125 apart in sqrt a
  // up to 25 (alpha' 0.038). (Four per decade and 0.25 were up to 26 % off the solver where R is
  // above 1e-4 of its value at x = 0.4, at alpha' 0.3-0.85; these 8.7 %, beyond x = 6 where the
  // solver's own far field is uncertain by as much.)
  for (int k = 0; k <= 32; ++k) t.a_h.push_back(1e-4 * std::pow(10.0, k / 8.0));
  for (int j = 1; j <= 32; ++j) t.a_h.push_back(std::pow(1.0 + 0.125 * j, 2));
  for (int i = 0; i <= 90; ++i) t.x.push_back(1e-3 * std::pow(10.0, i / 16.0));
  return t;
}

namespace {
std::vector<double> solve(const SkinStackTable& t, double tau_v, double a_e_v, const Layer* below) {
  return tables::solve(t.x, t.eta, t.g, tau_v, a_e_v, below);
}
// The top layer over an index-matched absorber (sigma_a = 1, sigma_s' = 1e-9 in units of s: no
// light comes back from below).
Layer absorber(const SkinStackTable& t) { return {1.0, 1e-9, kInfinity, t.eta, t.g}; }

Layer dermis(const SkinStackTable& t, double a_d_v) { return {a_d_v, t.dermis_ratio, kInfinity, t.eta, t.g}; }

// The light that reached the lower layer, on its own: R(k) of the stack minus R(k) of the top
// layer over the absorber, at the same frequencies, inverted by itself. The top layer's own
// reflection is the same arithmetic in both solves (the same azimuthal orders: the automatic ones
// are the same for every stack that is not thin), so the difference keeps the digits that the
// difference of the two inverted profiles loses: their inversion is noise below ~1e-8 of
// rho(0.01), and in a dark epidermis the light from below is smaller than that in the far field
// (asian skin at 450 nm was 10-41 % low at 0.45-0.59 mm, docs/accurate-solver.md, sec. 4).
// No singular part: the lower layer lies tau below the surface, so R(k) falls like e^(-tau k)
// (the frequencies end at 36 / tau, e^-36 of R(0)), and no light comes back along the beam (the
// layers are index-matched).
class LightFromBelow final : public RadialResponse {
 public:
  static constexpr double kK0 = 0.3 / 15.0, kDu = 0.125;
  static std::vector<double> frequencies(double tau_v) { return detail::frequency_nodes(36.0 / tau_v, kK0, kDu); }
  LightFromBelow(std::vector<double> k, std::vector<double> R) : k_(std::move(k)), R_(std::move(R)) {}
  double total() const override { return R_.front(); }
  double singular(double) const override { return 0.0; }
  double residual_k(double k) const override { return detail::interpolate_in_u(k_, R_, k, kK0, kDu); }

 private:
  std::vector<double> k_, R_;  // frequencies(tau) and R(k) there
};
LayerStack stack_of(const SkinStackTable& t, double tau_v, double a_e_v, const Layer& below) {
  LayerStack st;
  st.eta_above = 1.0;
  st.layers.push_back({a_e_v, 1.0, tau_v, t.eta, t.g});
  st.layers.push_back(below);
  return st;
}
// rho of the light from below at the x nodes, given R(k) of the top layer over the absorber at
// LightFromBelow::frequencies(tau).
std::vector<double> light_from_below(const SkinStackTable& t, double tau_v, double a_e_v, double a_d_v,
                              const std::vector<double>& R_top_k) {
  std::vector<double> k = LightFromBelow::frequencies(tau_v);
  std::vector<double> R = frequency_response(stack_of(t, tau_v, a_e_v, dermis(t, a_d_v)), k);
  for (std::size_t j = 0; j < R.size(); ++j) R[j] -= R_top_k[j];
  return solver_on(t.x).profile(LightFromBelow(std::move(k), std::move(R)));
}
std::vector<double> top_frequencies(const SkinStackTable& t, double tau_v, double a_e_v) {
  return frequency_response(stack_of(t, tau_v, a_e_v, absorber(t)), LightFromBelow::frequencies(tau_v));
}
}  // namespace

std::vector<double> SkinStackTable::solve_node(double tau_v, double a_e_v, double a_d_v) const {
  const Layer d = dermis(*this, a_d_v);
  return floored_log(solve(*this, tau_v, a_e_v, &d));
}

namespace {
// ln rho of the light from below, floored at kLowFloor of the peak of the whole (top + low) (so
// that a dark epidermis' light from below, down to ~e-32 of the peak, is its own smooth values and
// not the floor: ln rho falls linearly in tau, and a floored node bent the interpolation), and at
// kFloor of its own peak. Its far field can end in its inversion's noise well above that floor
// (~1e-9 of the whole peak in a thin epidermis over a dark dermis): continue_far_field().
constexpr double kLowFloor = 1e-15;
// The peak of the whole profile, top + low.
double whole_peak(const std::vector<double>& top, const std::vector<double>& low) {
  double peak = 0;
  for (std::size_t i = 0; i < top.size(); ++i) peak = std::max(peak, top[i] + low[i]);
  return peak;
}
std::vector<double> floored_low(const std::vector<double>& top, const std::vector<double>& low) {
  const double floor = std::max(kLowFloor * whole_peak(top, low), kFloor * *std::max_element(low.begin(), low.end()));
  std::vector<double> out(low.size());
  for (std::size_t i = 0; i < low.size(); ++i) out[i] = std::log(std::max(low[i], floor));
  return out;
}
}  // namespace

std::vector<double> SkinStackTable::solve_low(double tau_v, double a_e_v, double a_d_v) const {
  const Layer a = absorber(*this);
  return floored_low(solve(*this, tau_v, a_e_v, &a),
                     light_from_below(*this, tau_v, a_e_v, a_d_v, top_frequencies(*this, tau_v, a_e_v)));
}

std::vector<double> SkinStackTable::solve_top(double tau_v, double a_e_v) const {
  const Layer a = absorber(*this);
  return floored_log(solve(*this, tau_v, a_e_v, &a));
}

std::vector<double> SkinStackTable::solve_half_space(double a_v) const {
  return floored_log(solve(*this, kInfinity, a_v, nullptr));
}

namespace {
// Index of v among nodes, or npos.
std::size_t node_index(const std::vector<double>& nodes, double v) {
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (same_node(nodes[i], v)) return i;
  return std::string::npos;
}
// Per node of `nodes`, its index among `in` (npos where it is not one): a reused file's rows.
std::vector<std::size_t> node_indices(const std::vector<double>& in, const std::vector<double>& nodes) {
  std::vector<std::size_t> out;
  out.reserve(nodes.size());
  for (double v : nodes) out.push_back(node_index(in, v));
  return out;
}
// The lower layer's sigma_s' over the top layer's, the table's own where within 1e-9 of it.
double ratio_of(const SkinStackTable& t, const Layer& e, const Layer& d) {
  const double ratio = d.sigma_s_prime / e.sigma_s_prime;
  return std::abs(ratio - t.dermis_ratio) <= 1e-9 * t.dermis_ratio ? t.dermis_ratio : ratio;
}
}  // namespace

void SkinStackTable::compute(const ProgressCallback& progress, const SkinStackTable* reuse) {
  const std::size_t n_e = a_e.size(), n_d = a_d.size(), n_x = x.size();
  if (reuse && !(reuse->eta == eta && reuse->g == g && reuse->dermis_ratio == dermis_ratio && same_nodes(reuse->x, x)))
    throw InputError("reuse: the table to reuse has another geometry or x nodes than the one computed");
  const bool reuse_half = reuse && same_nodes(reuse->a_h, a_h);
  // Per (tau, a_e): its row in `reuse`, or npos (solved); per a_d its index there, or npos (its
  // rows solved, with the top layer's R(k) solved again for them).
  std::vector<std::size_t> from(tau.size() * n_e, std::string::npos), from_d(n_d, std::string::npos);
  if (reuse) {
    const std::vector<std::size_t> from_t = node_indices(reuse->tau, tau), from_e = node_indices(reuse->a_e, a_e);
    for (std::size_t i_t = 0; i_t < tau.size(); ++i_t)
      for (std::size_t i_e = 0; i_e < n_e; ++i_e)
        if (from_t[i_t] != std::string::npos && from_e[i_e] != std::string::npos)
          from[i_t * n_e + i_e] = from_t[i_t] * reuse->a_e.size() + from_e[i_e];
    from_d = node_indices(reuse->a_d, a_d);
  }
  const bool every_a_d = std::find(from_d.begin(), from_d.end(), std::string::npos) == from_d.end();
  auto copied = [&](std::size_t k_top, std::size_t i_d) { return from[k_top] != std::string::npos && from_d[i_d] != std::string::npos; };
  const std::size_t total = tau.size() * n_e * (n_d + 1) + a_h.size();
  ln_rho.assign(tau.size() * n_e * n_d * n_x, 0.0);
  ln_rho_top.assign(tau.size() * n_e * n_x, 0.0);
  ln_rho_half.assign(a_h.size() * n_x, 0.0);
  std::mutex m;
  std::size_t done = 0;
  auto tick = [&] {
    if (!progress) return;
    const std::lock_guard<std::mutex> lock(m);
    progress(++done, total);
  };
  // The top layers first (each lower-layer node subtracts its top layer's R(k)).
  std::vector<std::vector<double>> top(tau.size() * n_e), top_k(tau.size() * n_e);
  tbb::parallel_for(std::size_t{0}, tau.size() * n_e, [&](std::size_t k) {
    if (util::cancel::requested()) return;  // thrown below
    const Layer a = absorber(*this);
    if (from[k] != std::string::npos) {
      const auto src = reuse->ln_rho_top.begin() + static_cast<std::ptrdiff_t>(from[k] * n_x);
      std::copy(src, src + static_cast<std::ptrdiff_t>(n_x), ln_rho_top.begin() + static_cast<std::ptrdiff_t>(k * n_x));
      const std::size_t n_d_reuse = reuse->a_d.size();
      for (std::size_t i_d = 0; i_d < n_d; ++i_d) {
        if (from_d[i_d] == std::string::npos) continue;
        const auto row = reuse->ln_rho.begin() + static_cast<std::ptrdiff_t>((from[k] * n_d_reuse + from_d[i_d]) * n_x);
        std::copy(row, row + static_cast<std::ptrdiff_t>(n_x), ln_rho.begin() + static_cast<std::ptrdiff_t>((k * n_d + i_d) * n_x));
        tick();
      }
      tick();
      if (every_a_d) return;
      // (new a_d nodes: their light from below subtracts this top layer's R(k); its row stays the copy)
      top[k] = solve(*this, tau[k / n_e], a_e[k % n_e], &a);
      top_k[k] = top_frequencies(*this, tau[k / n_e], a_e[k % n_e]);
      return;
    }
    top[k] = solve(*this, tau[k / n_e], a_e[k % n_e], &a);
    top_k[k] = top_frequencies(*this, tau[k / n_e], a_e[k % n_e]);
    const std::vector<double> ln_top = floored_log(top[k]);
    std::copy(ln_top.begin(), ln_top.end(), ln_rho_top.begin() + static_cast<std::ptrdiff_t>(k * n_x));
    tick();
  });
  util::cancel::check();
  tbb::parallel_for(std::size_t{0}, a_h.size(), [&](std::size_t k) {
    if (util::cancel::requested()) return;
    if (reuse_half) {
      const auto src = reuse->ln_rho_half.begin() + static_cast<std::ptrdiff_t>(k * n_x);
      std::copy(src, src + static_cast<std::ptrdiff_t>(n_x), ln_rho_half.begin() + static_cast<std::ptrdiff_t>(k * n_x));
    } else {
      const std::vector<double> h = solve_half_space(a_h[k]);
      std::copy(h.begin(), h.end(), ln_rho_half.begin() + static_cast<std::ptrdiff_t>(k * n_x));
    }
    tick();
  });
  util::cancel::check();
  tbb::parallel_for(std::size_t{0}, tau.size() * n_e * n_d, [&](std::size_t k) {
    if (util::cancel::requested()) return;
    const std::size_t i_d = k % n_d, i_e = (k / n_d) % n_e, i_t = k / (n_d * n_e);
    if (copied(i_t * n_e + i_e, i_d)) return;  // copied with its top layer
    const std::size_t k_top = i_t * n_e + i_e;
    const std::vector<double> low =
        floored_low(top[k_top], light_from_below(*this, tau[i_t], a_e[i_e], a_d[i_d], top_k[k_top]));
    std::copy(low.begin(), low.end(), ln_rho.begin() + static_cast<std::ptrdiff_t>(k * n_x));
    tick();
  });
  util::cancel::check();
}

std::string SkinStackTable::to_csv() const {
  std::ostringstream os;
  os << "# Spectral Skin: radial profiles of the two-layer skin geometry in units of the epidermis'\n"
        "# reduced scattering s (tau = s d, a = sigma_a / s, x = r s, R(r) = s^2 rho(x)), computed by\n"
        "# this project's frequency-domain transport solver (FrequencyStack); the columns and their\n"
        "# use: include/skin/transport/skin_stack_table.hpp, docs/accurate-solver.md sec. 4.\n";
  os << "# provenance: " << provenance << '\n';
  os << "# eta: " << eta << "\n# g: " << g << "\n# dermis_ratio: " << dermis_ratio << '\n';
  os << "# tau: " << format_number_list(tau) << "\n# a_e: " << format_number_list(a_e)
     << "\n# a_d: " << format_number_list(a_d) << "\n# x: " << format_number_list(x) << '\n';
  if (!a_h.empty()) os << "# a_h: " << format_number_list(a_h) << '\n';
  os << "# Per (tau, a_e) first the top layer over an absorber (a_d = inf: the light that never\n"
        "# reaches the lower layer), then per a_d the light that reached it, solved on its own (R(k)\n"
        "# of the stack minus the top layer's, inverted): ln rho_low.\n"
        "# Then per a_h the half-space of the top layer's medium (tau = inf, a_e = a_h, a_d = inf).\n";
  os << "tau,a_e,a_d";
  for (std::size_t i = 0; i < x.size(); ++i) os << ",ln_rho_" << i;
  os << '\n';
  char buf[32];
  auto row = [&](double t, double e, const char* d, const double* v) {
    os << format_number_list({t, e}) << ',' << d;
    for (std::size_t i = 0; i < x.size(); ++i) {
      std::snprintf(buf, sizeof buf, ",%.4f", v[i]);
      os << buf;
    }
    os << '\n';
  };
  std::size_t k = 0, k_top = 0;
  for (double t : tau)
    for (double e : a_e) {
      row(t, e, "inf", ln_rho_top.data() + k_top++ * x.size());
      for (double d : a_d) row(t, e, format_number(d).c_str(), ln_rho.data() + k++ * x.size());
    }
  for (std::size_t i = 0; i < a_h.size(); ++i) row(kInfinity, a_h[i], "inf", ln_rho_half.data() + i * x.size());
  return os.str();
}

SkinStackTable SkinStackTable::parse(std::string_view text, std::string_view source) {
  const std::string src(source);
  const auto meta = csv_metadata(text);
  SkinStackTable t;
  t.provenance = meta.count("provenance") ? meta.at("provenance") : "";
  t.eta = metadata_number(meta, "eta", src);
  t.g = metadata_number(meta, "g", src);
  t.dermis_ratio = metadata_number(meta, "dermis_ratio", src);
  t.tau = metadata_numbers(meta, "tau", src);
  t.a_e = metadata_numbers(meta, "a_e", src);
  t.a_d = metadata_numbers(meta, "a_d", src);
  t.x = metadata_numbers(meta, "x", src);
  if (meta.count("a_h")) t.a_h = metadata_numbers(meta, "a_h", src);  // optional: half-spaces
  for (const auto& [v, key] : {std::pair{&t.tau, "tau"}, {&t.a_e, "a_e"}, {&t.a_d, "a_d"}, {&t.x, "x"}, {&t.a_h, "a_h"}}) {
    if (v == &t.a_h && v->empty()) continue;
    if (v->size() < 4) throw InputError(src + ": '" + key + "' needs at least 4 nodes");
    for (std::size_t i = 0; i < v->size(); ++i)
      if (!((*v)[i] >= 1e-9 && (*v)[i] <= 1e9) ||
          (i > 0 && !(std::sqrt((*v)[i]) > std::sqrt((*v)[i - 1]) && std::log((*v)[i]) > std::log((*v)[i - 1]))))
        throw InputError(src + ": '" + key + "' must lie within [1e-9, 1e9] and increase");
  }
  check_x_nodes(t.x, src);
  const Table data = parse_csv(text, src);
  const std::size_t n_x = t.x.size(), n_d = t.a_d.size();
  const std::size_t skin_rows = t.tau.size() * t.a_e.size() * (n_d + 1);
  const std::size_t rows = skin_rows + t.a_h.size();
  if (data.columns.size() != 3 + n_x)
    throw InputError(src + ": expected " + std::to_string(3 + n_x) + " columns, found " +
                     std::to_string(data.columns.size()));
  if (data.rows() != rows)
    throw InputError(src + ": expected " + std::to_string(rows) +
                     " rows (tau x a_e x (the top layer alone and each a_d), then a_h), found " +
                     std::to_string(data.rows()));
  t.ln_rho.resize(t.tau.size() * t.a_e.size() * n_d * n_x);
  t.ln_rho_top.resize(t.tau.size() * t.a_e.size() * n_x);
  t.ln_rho_half.resize(t.a_h.size() * n_x);
  for (std::size_t r = 0; r < rows; ++r) {
    const bool half = r >= skin_rows;
    const std::size_t j = r % (n_d + 1), i_e = (r / (n_d + 1)) % t.a_e.size(),
                      i_t = r / ((n_d + 1) * t.a_e.size()), i_h = r - std::min(r, skin_rows);
    const double want[3] = {half ? kInfinity : t.tau[i_t], half ? t.a_h[i_h] : t.a_e[i_e],
                            half || j == 0 ? kInfinity : t.a_d[j - 1]};
    for (int c = 0; c < 3; ++c) {
      const double v = data.data[static_cast<std::size_t>(c)][r];
      if (!(want[c] == kInfinity ? v == kInfinity : std::abs(v / want[c] - 1) <= 1e-6))
        throw InputError(src + ": row " + std::to_string(r + 1) + " is not node (tau, a_e, a_d) = (" +
                         format_number(want[0]) + ", " + format_number(want[1]) + ", " +
                         format_number(want[2]) + ")");
    }
    double* out = half     ? t.ln_rho_half.data() + i_h * n_x
                  : j == 0 ? t.ln_rho_top.data() + (i_t * t.a_e.size() + i_e) * n_x
                           : t.ln_rho.data() + ((i_t * t.a_e.size() + i_e) * n_d + j - 1) * n_x;
    for (std::size_t i = 0; i < n_x; ++i) out[i] = data.data[3 + i][r];
    check_row(out, n_x, src, r + 1, data.columns);
  }
  return t;
}

const SkinStackTable& SkinStackTable::builtin() {
  static const SkinStackTable t = [] {
    // (Parsed in turn: on both cores at once a process started 0.26 s instead of 0.30 s, idle,
    // but took ~15 % more CPU under the sanitizers, where the suite runs two tests at a time.)
    SkinStackTable table = parse(util::data::embedded("skin_stack_profiles.csv"), "skin_stack_profiles.csv");
    static SkinStackOffsets o = SkinStackOffsets::parse(util::data::embedded("skin_stack_offsets.csv"), "skin_stack_offsets.csv");
    static SkinStackCross c = SkinStackCross::parse(util::data::embedded("skin_stack_cross.csv"), "skin_stack_cross.csv");
    // The offsets are the table's: its geometry, coarse nodes among the table's, every k-th x.
    bool ok = o.base[0] == table.g && o.base[1] == table.eta && o.base[2] == table.dermis_ratio &&
              o.x.size() >= 4 && (table.x.size() - 1) % (o.x.size() - 1) == 0;
    const std::size_t stride = ok ? (table.x.size() - 1) / (o.x.size() - 1) : 0;
    for (std::size_t i = 0; ok && i < o.x.size(); ++i) ok = same_node(o.x[i], table.x[stride * i]);
    for (const auto& [coarse, fine] : {std::pair{&o.tau, &table.tau}, {&o.a_e, &table.a_e}, {&o.a_d, &table.a_d}})
      for (double v : *coarse) ok = ok && node_index(*fine, v) != std::string::npos;
    // ... and span them (gap() asks the table's range: a read inside it is inside the offsets'),
    // but for a_e and tau, whose offsets may end short of the table's and hold their values beyond.
    auto spans = [](const std::vector<double>& own, const std::vector<double>& fine, bool held) {
      return same_node(own.front(), fine.front()) && (same_node(own.back(), fine.back()) || (held && own.back() < fine.back()));
    };
    for (int a = 0; a < SkinStackOffsets::kAxes; ++a)
      for (const auto& [own, fine, held] : {std::tuple{&o.a_e_of(a), &table.a_e, true}, {&o.a_d_of(a), &table.a_d, false}}) {
        ok = ok && spans(*own, *fine, held);
        for (double v : *own) ok = ok && node_index(*fine, v) != std::string::npos;
      }
    for (const auto& [coarse, fine, held] : {std::tuple{&o.tau, &table.tau, true}, {&o.a_e, &table.a_e, true}, {&o.a_d, &table.a_d, false}})
      ok = ok && spans(*coarse, *fine, held);
    if (!ok) throw std::logic_error("skin_stack_offsets.csv does not belong to skin_stack_profiles.csv");
    o.settle(table);
    table.settle();  // (after the offsets')
    // The cross terms are the offsets': their base, their axes' ends among the offsets' nodes (an
    // axis' offsets may reach farther than its corners: combined reads stop where the terms reach,
    // gap()), their nodes.
    for (std::size_t a = 0; a < SkinStackOffsets::kAxes; ++a)
      for (double end : c.ends[a]) ok = ok && c.base[a] == o.base[a] && node_index(o.nodes[a], end) != std::string::npos;
    if (!ok) throw std::logic_error("skin_stack_cross.csv does not belong to skin_stack_offsets.csv");
    c.settle(table, o);  // (checks the nodes)
    o.cross = &c;
    table.offsets = &o;
    return table;
  }();
  return t;
}

namespace {
// The darkest dermis (sigma_a over the top layer's sigma_s') read with the cross terms.
constexpr double kCombinedDarkestDermis = 0.5;
// ... unless the top layer is at least this thick (sigma_s' d).
constexpr double kCombinedDarkDermisThinnest = 0.35;
// Another dermis ratio with another g is solved under a top layer thinner than this (sigma_s' d).
constexpr double kCombinedGRatioThinnest = 0.117;
// Another dermis ratio with g above the table's under a thin top layer. Without corners above g
// 0.9 (the built-in cross terms until 2026-12-07) the g 0.7 ones are continued through the base
// (SkinStackCross::add), and with another dermis ratio under a thin top layer that missed the
// solver's profile (measured 2026-12-06 over random domain skins with tau 0.078-0.4, each read at
// a fixed g, worst above 1e-4 of R(0.02 mm)): 14 skins at g 0.9 2.3 %, 0.93 4.0 %, 0.95 6.2 %
// (ratio 0.2-0.27; the others 3.1 %), 0.96 8.7 %, 0.97 25 % (ratio 0.2-0.29 at 1.3-1.5 mm; the
// others 6.2 %); 12 others, whose worst (ratio 0.24, tau 0.096, index 1.55) grows with g: 2.9 %
// at 0.9, 4.1 % at 0.91, 5.2 % at 0.92, 6.3 % at 0.93, 7.5 % at 0.94. With the g 0.95 corners
// (since 2026-12-07) and the far field's rules of SkinStackOffsets::add such reads still missed a
// Monte Carlo (2e6 photons, docs/accurate-solver.md, sec. 4) under a thin top layer with a low
// ratio: tau 0.12, g 0.97, ratio 0.24 -20 % at 1.5 mm (1.44 times what 5 % + 3 SE allow); tau
// 0.22, g 0.954, ratio 0.24, +15 % at 1.9 mm (1.25); tau 0.38, g 0.946, ratio 0.29, +20 % at 0.58
// mm (1.47); tau 0.40, g 0.97, ratio 0.23 +13 % at 1.4 mm (1.04; -75 %, 5.6 times, before
// those rules); eight with tau 0.43-0.69 and ratio 0.20-0.28 passed (0.29-0.87). Such skin is
// solved: g above kMirroredGThin with the ratio below kMirroredLowRatio under tau below
// kMirroredThinnest; and without corners above the table's g, g above kMirroredGAllRatios with any
// other ratio (under thicker top layers too such reads missed the Monte Carlo: tau 0.48, g 0.97,
// index 1.55, ratio 2, 1.15 times; with the corners 0.34).
constexpr double kMirroredGThin = 0.91, kMirroredGAllRatios = 0.955, kMirroredLowRatio = 0.35, kMirroredThinnest = 0.45;
// g above kHighGDarkG under a top layer darker than kHighGDarkTop (sigma_a / sigma_s') is solved:
// the g offsets there miss the solver (measured 2026-12-07 on a grid at index 1.4 and the table's
// ratio, a_d 1, tau 0.6-3, worst above 1e-4 of R(0.02 mm): g 0.95 and 0.97 with a_e 3.1-6 2.7-12 %,
// 5-12 % from tau 1 (the g 0.95 node itself 7.4 % at tau 2, a_e 4.55); with a_e 2.0-2.66 at most
// 4.1 %; g 0.93 at most 3.5 % at every a_e), and against 2 x 10^6 photons two such reads at g 0.97
// (tau 1.66, a_e 3.35, ratio 0.59; tau 1.89, a_e 3.47, ratio 0.21: a draw of the skin domain)
// were 1.14 and 1.05 times what 5 % + 3 SE allow, -9 and -13 % at 0.075 and 0.15 mm.
constexpr double kHighGDarkG = 0.94, kHighGDarkTop = 2.8;
}  // namespace

std::string SkinStackTable::gap(const LayerStack& stack) const {
  const auto& ls = stack.layers;
  auto inside = [](const std::vector<double>& v, double t) { return t >= v.front() && t <= v.back(); };
  if (ls.size() == 1) {  // the half-space
    const Layer& h = ls[0];
    if (a_h.empty()) return "the skin table has no half-space nodes";
    if (stack.eta_above != 1.0) return "the medium above is not air";
    if (h.eta != eta) return "index is not the skin table's " + format_number(eta);
    if (h.g != g) return "g is not the skin table's " + format_number(g);
    if (!h.semi_infinite()) return "a slab, not a half-space";
    const double a = h.sigma_a / h.sigma_s_prime;
    if (!(h.sigma_s_prime > 0) || !inside(a_h, a))
      return "sigma_a / sigma_s' = " + format_number(a) + " is outside the skin table's half-space [" +
             format_number(a_h.front()) + ", " + format_number(a_h.back()) + "]";
    return {};
  }
  if (ls.size() != 2) return "neither a half-space nor two layers";
  const Layer &e = ls[0], &d = ls[1];
  if (stack.eta_above != 1.0) return "the medium above is not air";
  if (e.semi_infinite() || !d.semi_infinite()) return "not a finite layer over a half-space";
  const double s = e.sigma_s_prime;
  if (!(s > 0) || !(d.sigma_s_prime > 0)) return "a layer does not scatter";
  const double ratio = ratio_of(*this, e, d);
  if (!offsets) {
    if (e.eta != eta || d.eta != eta) return "index is not the skin table's " + format_number(eta);
    if (e.g != g || d.g != g) return "g is not the skin table's " + format_number(g);
    if (ratio != dermis_ratio) return "the lower layer's sigma_s' is not " + format_number(dermis_ratio) + " x the top layer's";
  } else {
    if (e.eta != d.eta) return "the two layers' indices differ";
    if (e.g != d.g) return "the two layers' g differ";
    std::string why = offsets->gap(e.g, e.eta, ratio);
    if (!why.empty()) return why;
  }
  const double t = s * e.thickness, ae = e.sigma_a / s, ad = d.sigma_a / s;
  if (!inside(tau, t)) return "sigma_s' d = " + format_number(t) + " is outside the skin table's [" + format_number(tau.front()) + ", " + format_number(tau.back()) + "]";
  if (!inside(a_e, ae)) return "top sigma_a / sigma_s' = " + format_number(ae) + " is outside the skin table's [" + format_number(a_e.front()) + ", " + format_number(a_e.back()) + "]";
  if (!inside(a_d, ad)) return "lower sigma_a / top sigma_s' = " + format_number(ad) + " is outside the skin table's [" + format_number(a_d.front()) + ", " + format_number(a_d.back()) + "]";
  // Another g, index or dermis ratio over an epidermis darker than kOffsetsHeldReach: the
  // offsets, held beyond their last a_e node (6.93), drift from the solver's there.
  if (offsets && !(e.g == g && e.eta == eta && ratio == dermis_ratio) && ae > kOffsetsHeldReach)
    return "top sigma_a / sigma_s' = " + format_number(ae) + " above " + format_number(kOffsetsHeldReach) +
           " with another g, index or dermis scattering ratio than the skin table's (its offsets end at " +
           format_number(kOffsetsDarkestTop) + ")";
  if (offsets && e.g > kHighGDarkG && ae > kHighGDarkTop)
    return "g = " + format_number(e.g) + " above " + format_number(kHighGDarkG) + " over a top layer with sigma_a / sigma_s' = " +
           format_number(ae) + " above " + format_number(kHighGDarkTop) + " (the skin table's g offsets miss such skin)";
  // Another dermis ratio with another g or index takes the cross terms, which miss a dark dermis'
  // far field: there the corners' solves are near their floor (~1e-9 of the peak), within reach
  // of a Monte Carlo (measured: index 1.49, ratio 2, g 0.7 with a_d 3.3 at 409 nm 39 % off the
  // solver above 1e-4 of R(0.02 mm); index 1.54, ratio 1.41 with a_d 0.8 at 455 nm +19 to +38 % at
  // 0.21-0.23 mm against 4e6 photons, SE 2-3 %). Such skin is solved under a thin top layer (tau
  // below 0.35: 14 of 51 random ones beyond 5 % of the solver, worst 103 %); under a thicker one
  // the combined read is as close to the solver as the offsets' alone over the same skin with the
  // table's ratio (60 random ones, 2026-12-06: median 0.9 % above 1e-4 both, the same 3 beyond 5 %,
  // with g above 0.95), and is read.
  if (offsets && ratio != dermis_ratio && (e.g != g || e.eta != eta) && ad > kCombinedDarkestDermis &&
      t < kCombinedDarkDermisThinnest)
    return "another dermis scattering ratio together with another g or index over a dermis with sigma_a / the top "
           "layer's sigma_s' = " + format_number(ad) + " above " + format_number(kCombinedDarkestDermis) +
           " under a top layer with sigma_s' d = " + format_number(t) + " below " + format_number(kCombinedDarkDermisThinnest) +
           " (the skin table's cross terms miss its far field)";
  // (The first only where the cross terms are continued there: no corners above the table's g.)
  const bool g_continued = offsets && offsets->cross && offsets->cross->ends[0][1] == offsets->cross->base[0];
  if (offsets && ratio != dermis_ratio && e.g > kMirroredGThin && ratio < kMirroredLowRatio && t < kMirroredThinnest)
    return "g = " + format_number(e.g) + " above " + format_number(kMirroredGThin) + " together with another dermis scattering ratio (" +
           format_number(ratio) + " below " + format_number(kMirroredLowRatio) + ") under a top layer with sigma_s' d = " +
           format_number(t) + " below " + format_number(kMirroredThinnest) + " (the skin table's read misses such skin's far field)";
  if (g_continued && ratio != dermis_ratio && e.g > kMirroredGAllRatios)
    return "g = " + format_number(e.g) + " above " + format_number(kMirroredGAllRatios) + " together with another dermis scattering ratio (" +
           format_number(ratio) + ") (the skin table has no cross terms for g above " + format_number(g) +
           ": continued from below, they miss such skin)";
  // Another dermis ratio together with another g under the thinnest epidermis: within about tau
  // of the beam the solves' split into the two parts rings at the thinnest tau nodes, and the g
  // and dermis ratio cross terms there turn that ringing into a bump (docs/accurate-solver.md,
  // sec. 4): a 0.066 mm epidermis with s 1.19 /mm (tau 0.078, a_e 2.8, a_d 0.10, g 0.76, index
  // 1.41, ratio 0.26, at 717 nm) read +34 % off a 4e6-photon Monte Carlo at 0.015-0.02 mm, where
  // 5 % + 3 SE allow 10.6 %.
  if (offsets && ratio != dermis_ratio && e.g != g && t < kCombinedGRatioThinnest)
    return "another dermis scattering ratio together with another g under a top layer with sigma_s' d = " + format_number(t) +
           " below " + format_number(kCombinedGRatioThinnest) + " (the skin table's cross terms ring near the beam there)";
  return {};
}

std::vector<double> SkinStackTable::node(std::size_t i_t, std::size_t i_e, std::size_t i_d) const {
  const std::size_t k = (i_t * a_e.size() + i_e) * a_d.size() + i_d, n_x = x.size();
  const double* top = ln_rho_top.data() + (i_t * a_e.size() + i_e) * n_x;
  std::vector<double> out(n_x);
  for (std::size_t m = 0; m < n_x; ++m) out[m] = log_sum(top[m], ln_rho[k * n_x + m]);
  return out;
}

std::vector<double> SkinStackTable::ln_rho_half_space_at(double a) const {
  // In sqrt a, as the top layer's a_e.
  const Lagrange4Stencil sh = lagrange4_stencil(mapped(a_h, sqrt_of), std::sqrt(a));
  const std::size_t n_x = x.size();
  std::vector<double> out(n_x, 0.0);
  for (std::size_t i = 0; i < 4; ++i) {
    const double* v = ln_rho_half.data() + (sh.first + i) * n_x;
    for (std::size_t m = 0; m < n_x; ++m) out[m] += sh.weights[i] * v[m];
  }
  for (double& v : out) v = clamp_ln(v);
  return out;
}

namespace {
// ln rho of the two parts added (in place of top).
std::vector<double> added(std::vector<double> top, const std::vector<double>& below) {
  for (std::size_t m = 0; m < top.size(); ++m) top[m] = clamp_ln(log_sum(clamp_ln(top[m]), clamp_ln(below[m])));
  return top;
}
}  // namespace

std::vector<double> SkinStackTable::ln_rho_at(double t, double ae, double ad) const {
  std::vector<double> top, below;
  ln_parts_at(t, ae, ad, top, below);
  return added(std::move(top), below);
}

void SkinStackTable::ln_parts_at(double t, double ae, double ad, std::vector<double>& top,
                                 std::vector<double>& below) const {
  // The top layer alone in ln tau (as a power of its thickness near the beam); the light from
  // below in tau (it crosses the top layer twice: ln rho falls linearly in tau).
  const Lagrange4Stencil st_top = lagrange4_stencil(mapped(tau, log_of), std::log(t));
  const Lagrange4Stencil st = lagrange4_stencil(tau, t);
  const Lagrange4Stencil se = lagrange4_stencil(mapped(a_e, sqrt_of), std::sqrt(ae));
  const Lagrange4Stencil sd = lagrange4_stencil(mapped(a_d, sqrt_of), std::sqrt(ad));
  const std::size_t n_x = x.size();
  top.assign(n_x, 0.0);
  below.assign(n_x, 0.0);
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j) {
      const double w = st_top.weights[i] * se.weights[j];
      const double* v = ln_rho_top.data() + ((st_top.first + i) * a_e.size() + se.first + j) * n_x;
      for (std::size_t m = 0; m < n_x; ++m) top[m] += w * v[m];
      for (std::size_t l = 0; l < 4; ++l) {
        const double wb = st.weights[i] * se.weights[j] * sd.weights[l];
        const std::size_t k = ((st.first + i) * a_e.size() + se.first + j) * a_d.size() + sd.first + l;
        const double* b = ln_rho.data() + k * n_x;
        for (std::size_t m = 0; m < n_x; ++m) below[m] += wb * b[m];
      }
    }
}

namespace {
// Within 0.3 of the top layer's depth from the beam (x < 0.3 tau) the light from below holds its
// value there. The solver does not resolve it that near: its R(k) turns negative at high k
// (tau 0.15: -3e-4 of R(0) at k ~ 50), where the light from a depth tau should fall like
// e^(-tau k), so its profile dips below 0 within ~0.1 tau of the beam (tau 0.15: -0.07 at
// x = 0.001, where it is ~+0.05 at 0.02-0.1; FrequencyStack's own profiles of the stack and of the
// top layer differ the same way), and out to ~0.3 tau the split of the solve into the top layer's
// light and the light from below rings (their sum does not).
// Offsets between such values jump from the floor to real values there, and their cubic
// interpolation in ln x overshoots: a spike that the scaling to R_d spreads over the whole profile
// (measured: +9 % of the integral, -10 % at every radius of a thin epidermis with index 1.52 and
// dermis ratio 2; docs/accurate-solver.md, sec. 4). Interpolated across nodes, the ringing parts
// no longer cancel: held to 0.1 tau only, a 0.11 mm epidermis (tau 0.19) with g 0.71, index 1.34
// and dermis ratio 2 read +8.6 % off a 4e6-photon Monte Carlo at 0.02-0.03 mm, where 7.7 % is
// allowed; held to 0.3 tau, -1.7 %. That light comes from a depth tau, so it varies little across
// x < 0.3 tau, and there it is small against the top layer's own.
void hold_low_near_beam(const std::vector<double>& x, double t, std::vector<double>& low) {
  constexpr double kHeldWithin = 0.3;  // of tau
  std::size_t k = 0;
  while (k + 1 < x.size() && x[k] < kHeldWithin * t) ++k;
  for (std::size_t i = 0; i < k; ++i) low[i] = low[k];
}
}  // namespace

SkinStackProfile::SkinStackProfile(const SkinStackTable& table, const LayerStack& stack, double R_d)
    : x_(&table.x) {
  const Layer& e = stack.layers.at(0);
  s_ = e.sigma_s_prime;
  if (stack.layers.size() == 1) {
    ln_rho_ = table.ln_rho_half_space_at(e.sigma_a / s_);
  } else {
    const Layer& d = stack.layers[1];
    const double t = s_ * e.thickness, ae = e.sigma_a / s_, ad = d.sigma_a / s_;
    const double ratio = ratio_of(table, e, d);
    std::vector<double> top, low;
    table.ln_parts_at(t, ae, ad, top, low);
    // Another geometry: the offsets of each axis added to the parts (none at the table's own).
    if (!(e.g == table.g && e.eta == table.eta && ratio == table.dermis_ratio)) {
      table.offsets->add(t, ae, ad, e.g, e.eta, ratio, table, top, low);
      hold_low_near_beam(table.x, t, low);
    }
    ln_rho_ = added(std::move(top), low);
  }
  scale_to(R_d);
}

SkinStackProfile::SkinStackProfile(const std::vector<double>& x, std::vector<double> ln_rho, double s, double R_d)
    : x_(&x), s_(s), ln_rho_(std::move(ln_rho)) {
  scale_to(R_d);
}

void SkinStackProfile::scale_to(double R_d) {
  const std::vector<double>& xs = *x_;
  ln_x_ = mapped(xs, log_of);
  const std::size_t n = ln_x_.size();
  h_ = (ln_x_.back() - ln_x_.front()) / static_cast<double>(n - 1);
  cutoff_ = *std::max_element(ln_rho_.begin(), ln_rho_.end()) + std::log(10 * kFloor);
  // Near the beam rho grows like a power of 1 / x (single scattering: 1 / x): continued from the
  // first two nodes down to a tenth of the first x node, flat below.
  power_ = std::clamp((ln_rho_[1] - ln_rho_[0]) / h_, -1.9, 0.0);
  // Beyond the last node: ln rho linear in x, falling (0 if it does not fall).
  const double x1 = xs[n - 1];
  decay_ = std::max(0.0, -(ln_rho_[n - 1] - ln_rho_[n - 2]) / (x1 - xs[n - 2]));
  // 2 pi int x rho dx of exactly what operator() returns: Simpson on the even ln x grid (as
  // 2 pi int x^2 rho d(ln x)), the power law and the flat disc below it, the exponential beyond.
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double f = ln_rho_[i] < cutoff_ ? 0.0 : std::exp(2 * ln_x_[i] + ln_rho_[i]);
    sum += ((i == 0 || i == n - 1) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0)) * f;
  }
  double integral = 2 * std::numbers::pi * sum * h_ / 3.0;
  const double x0 = xs.front(), xf = x0 / 10, rho0 = std::exp(ln_rho_[0]);
  const double rho_f = rho0 * std::pow(0.1, power_);
  integral += 2 * std::numbers::pi * rho0 * std::pow(x0, -power_) *
              (std::pow(x0, 2 + power_) - std::pow(xf, 2 + power_)) / (2 + power_);
  integral += std::numbers::pi * xf * xf * rho_f;
  if (decay_ > 0 && ln_rho_[n - 1] >= cutoff_)
    integral += 2 * std::numbers::pi * std::exp(ln_rho_[n - 1]) * (x1 / decay_ + 1 / (decay_ * decay_));
  scale_ = integral > 0 ? R_d * s_ * s_ / integral : 0.0;
  if (!std::isfinite(scale_)) scale_ = 0.0;
}

double SkinStackProfile::operator()(double r) const {
  const std::size_t n = ln_x_.size();
  const double x = r * s_, x0 = (*x_).front();
  if (x < x0) return scale_ * std::exp(ln_rho_[0]) * std::pow(std::max(x, x0 / 10) / x0, power_);
  const double lx = std::log(x);
  if (lx >= ln_x_.back()) {
    if (decay_ == 0 || ln_rho_[n - 1] < cutoff_) return 0.0;
    return scale_ * std::exp(ln_rho_[n - 1] - decay_ * (x - (*x_)[n - 1]));
  }
  const double u = (lx - ln_x_.front()) / h_;
  const std::size_t i = std::min(static_cast<std::size_t>(u), n - 2);
  const std::size_t i0 = std::min(i > 0 ? i - 1 : 0, n - 4);
  const std::array<double, 4> w = lagrange4_weights(u - static_cast<double>(i0));
  double v = 0;
  for (std::size_t a = 0; a < 4; ++a) v += w[a] * ln_rho_[i0 + a];
  if (v < cutoff_) return 0.0;
  const double out = scale_ * std::exp(clamp_ln(v));
  return std::isfinite(out) ? out : 0.0;  // (a table of nodes ~1e-9 apart in x: see clamp_ln)
}

// --- Offsets for another g, index or dermis ratio --------------------------------------------

namespace {
// A part counts where it is above this of its node's peak: the top layer alone to 1e-9 (its
// inversion's noise floor), the light from below, solved on its own, to 1e-14 (at 1e-9 a dark
// epidermis' far field held the offset of ~0.6 mm over 0.59-0.71 mm of asian skin at 450 nm
// under a 1.4 dermis ratio, and read 14-62 % high there; where its own far field ends in noise
// above that, settle() continues it).
constexpr double kOffsetValidTop = 1e-9;
constexpr double kOffsetValidLow = 1e-14;
// The cross terms keep their value beyond this x (in units of 1 / s; SkinStackCross::add).
constexpr double kCrossHeldFrom = 20.0;
// A node's cross terms count where its corner's light from below and the table's are both above
// this of the node's peak (SkinStackCross::settle); beyond, they keep their last value. The
// corners' solves reach their floor near 1e-9 of the peak, and a term between floored
// neighbours is noise: a 0.039 mm epidermis with g 0.835, index 1.35 and dermis ratio 1.3 at
// 451 nm (domain draw 23) read +6.3 % off the solver at 0.34 mm (x 5.4, ~5e-8 of the peak), +10.7 %
// off a 2e6-photon Monte Carlo where 9.7 % is allowed; held, +3.9 % off the solver.
constexpr double kCrossValid = 1e-8;
constexpr double kMaxOffset = 20;       // |offset| in ln rho, as stored and parsed
// Beyond the g axis' last node the offsets continue linearly in 1 - g through the last two nodes,
// this much of their interval farther (0.95 and 0.9: to g 0.97, the domain's top). As g -> 1 at a
// fixed reduced scattering the profile tends to a limit, so the offset is smooth in 1 - g there:
// the same rule from 0.8 and 0.9 to 0.95 (half their interval) read the solved 0.95 node's whole
// profile at its 26839 values above 1e-4 of each node's peak with median 0.85 %, 95 % within
// 3.0 %, worst 34 % (at tau 0.078); in ln(1 - g) 3-4 times worse. Read skins with g 0.95-0.97 are
// median 2.9 % off the solver, at most 16 % (docs/accurate-solver.md, sec. 4).
constexpr double kGContinued = 0.4;
// The largest g the offsets read: the last node, or continued beyond it.
double g_reach(const std::vector<double>& g_nodes) {
  const std::size_t n = g_nodes.size();
  if (n < 2) return g_nodes.back();
  return g_nodes[n - 1] + kGContinued * (g_nodes[n - 1] - g_nodes[n - 2]);
}
// The variable each axis is interpolated in: ln(1 - g), eta, ln ratio.
double axis_variable(int axis, double v) { return axis == 0 ? std::log(1 - v) : axis == 2 ? std::log(v) : v; }
// Its inverse: the axis' value at u.
double axis_value(int axis, double u) { return axis == 0 ? 1 - std::exp(u) : axis == 2 ? std::exp(u) : u; }
std::vector<double> axis_variables(int axis, const std::vector<double>& nodes) {
  std::vector<double> out(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) out[i] = axis_variable(axis, nodes[i]);
  if (axis == 0) std::reverse(out.begin(), out.end());  // ln(1 - g) falls as g grows
  return out;
}
// Each value where ok is false becomes that of the nearest x after the last ok one before it,
// or before that, the first ok one (unchanged where none is ok).
void hold_where_not(double* row, const std::vector<char>& ok) {
  const std::size_t n = ok.size();
  const auto first = static_cast<std::size_t>(std::find(ok.begin(), ok.end(), 1) - ok.begin());
  if (first == n) return;
  for (std::size_t i = 0; i < first; ++i) row[i] = row[first];
  for (std::size_t i = first + 1, last = first; i < n; ++i)
    if (ok[i]) last = i;
    else row[i] = row[last];
}
// new - base where both parts count; elsewhere the offset of the nearest x where they do (0 if
// nowhere).
std::vector<double> offset_row(const std::vector<double>& ln_new, double ln_new_peak, const double* ln_base,
                               double ln_base_peak, double valid) {
  const std::size_t n = ln_new.size();
  std::vector<double> d(n, 0.0);
  std::vector<char> ok(n, 0);
  const double lv = std::log(valid);
  for (std::size_t i = 0; i < n; ++i) {
    ok[i] = ln_new[i] > ln_new_peak + lv && ln_base[i] > ln_base_peak + lv;
    if (ok[i]) d[i] = std::clamp(ln_new[i] - ln_base[i], -kMaxOffset, kMaxOffset);
  }
  hold_where_not(d.data(), ok);
  return d;
}
// The offsets of one node against a base (ln rho of its parts on the table's x), taken at the x
// that pick(row) keeps: of the top layer alone, solved (R on the table's x) ...
template <class Pick>
std::vector<double> top_offset(const std::vector<double>& top, const std::vector<double>& ln_base_top, Pick pick) {
  const std::vector<double> b = pick(ln_base_top);
  return offset_row(pick(floored_log(top)), std::log(*std::max_element(top.begin(), top.end())), b.data(),
                    *std::max_element(b.begin(), b.end()), kOffsetValidTop);
}
// ... and of the light from below, solved for geo over the top layer `top` (R) whose R(k) is top_k.
template <class Pick>
std::vector<double> low_offset(const SkinStackTable& geo, double t, double e, double d, const std::vector<double>& top,
                               const std::vector<double>& top_k, const std::vector<double>& ln_base_top,
                               const std::vector<double>& ln_base_low, Pick pick) {
  const std::vector<double> low = light_from_below(geo, t, e, d, top_k);
  double base_peak = -1e300;  // the base's peak of the whole profile at this node
  for (std::size_t i = 0; i < ln_base_top.size(); ++i) base_peak = std::max(base_peak, log_sum(ln_base_top[i], ln_base_low[i]));
  const std::vector<double> b = pick(ln_base_low);
  return offset_row(pick(floored_low(top, low)), std::log(whole_peak(top, low)), b.data(), base_peak, kOffsetValidLow);
}
}  // namespace

SkinStackOffsets SkinStackOffsets::default_nodes(const SkinStackTable& table) {
  SkinStackOffsets o;
  o.base = {table.g, table.eta, table.dermis_ratio};
  o.nodes[0] = {0.7, 0.8, 0.9, 0.95, 0.97};
  o.nodes[1] = {1.33, 1.4, 1.47, 1.55};
  o.nodes[2] = {0.2, 0.3, 0.5, 0.75, 1.0, 1.4, 2.0};
  // Every tau node up to 10.1 (a thin top layer's offsets change fast with its depth; beyond, held:
  // kOffsetsThickestTop) and a_e up to 6.93 (kOffsetsDarkestTop); a_e and a_d every
  // other up to 0.4, then 0.5 apart in sqrt a (and the last node); x every other (8 per decade).
  for (double v : table.tau)
    if (v <= kOffsetsThickestTop) o.tau.push_back(v);
  auto thin = [](const std::vector<double>& v) {
    std::vector<double> out;
    double last_sqrt = -1;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const bool log_part = v[i] <= 0.4 * (1 + 1e-9);
      if (log_part ? i % 2 == 0 : std::sqrt(v[i]) - last_sqrt >= 0.5 - 1e-4 || i + 1 == v.size()) {
        out.push_back(v[i]);
        last_sqrt = std::sqrt(v[i]);
      }
    }
    return out;
  };
  std::vector<double> table_a_e;  // up to kOffsetsDarkestTop (held beyond)
  for (double v : table.a_e)
    if (v <= kOffsetsDarkestTop * (1 + 1e-6)) table_a_e.push_back(v);
  o.a_e = thin(table_a_e);
  o.a_d = thin(table.a_d);
  for (std::size_t i = 0; i < table.x.size(); i += 2) o.x.push_back(table.x[i]);
  // The dermis ratio's a_e and a_d: above 0.4 every other of the table's a_e and every a_d (0.25
  // apart in sqrt a, twice as fine as the others'). Its offset's far field is the light's path
  // through the lower layer against the top's, which changes fast there (x 6.5: 0.2 off the
  // solver across a_e 0.4 and 1.28, 0.04 with a node between; x 7.5, across a_d 0.4 and 1.28: 0.54,
  // 0.01; docs/accurate-solver.md, sec. 4).
  std::vector<double>&ratio_e = o.axis_a_e[2], &ratio_d = o.axis_a_d[2];
  for (std::size_t i = 0, k = 0; i < table_a_e.size(); ++i) {
    const bool log_part = table_a_e[i] <= 0.4 * (1 + 1e-9);
    if (log_part ? std::find(o.a_e.begin(), o.a_e.end(), table_a_e[i]) != o.a_e.end() : ++k % 2 == 0 || i + 1 == table_a_e.size())
      ratio_e.push_back(table_a_e[i]);
  }
  for (double v : table.a_d)
    if (v > 0.4 * (1 + 1e-9) || std::find(o.a_d.begin(), o.a_d.end(), v) != o.a_d.end()) ratio_d.push_back(v);
  return o;
}

std::size_t SkinStackOffsets::low_row(int axis, std::size_t i_t, std::size_t i_e, std::size_t i_d) const {
  const std::vector<double>&ae = a_e_of(axis), &ad = a_d_of(axis);
  const std::size_t e = node_index(ae, a_e.at(i_e)), d = node_index(ad, a_d.at(i_d));
  if (e == std::string::npos || d == std::string::npos) throw std::logic_error("skin table offsets: an axis' nodes miss the coarse ones");
  return (i_t * ae.size() + e) * ad.size() + d;
}

std::size_t SkinStackOffsets::top_row(int axis, std::size_t i_t, std::size_t i_e) const {
  const std::vector<double>& ae = a_e_of(axis);
  const std::size_t e = node_index(ae, a_e.at(i_e));
  if (e == std::string::npos) throw std::logic_error("skin table offsets: an axis' nodes miss the coarse ones");
  return i_t * ae.size() + e;
}

void SkinStackOffsets::compute(const SkinStackTable& table, const ProgressCallback& progress,
                               const SkinStackOffsets* reuse) {
  const std::size_t n_t = tau.size(), n_x = x.size();
  // Coarse nodes -> the table's nodes.
  auto indices = [](const std::vector<double>& coarse, const std::vector<double>& fine, const char* key) {
    std::vector<std::size_t> out;
    for (double v : coarse) {
      const std::size_t i = node_index(fine, v);
      if (i == std::string::npos)
        throw InputError(std::string("skin table offsets: the ") + key + " node " + format_number(v) + " is not a node of the table");
      out.push_back(i);
    }
    return out;
  };
  const auto it = indices(tau, table.tau, "tau"), ix = indices(x, table.x, "x");
  std::array<std::vector<std::size_t>, kAxes> ie, id;  // per axis, its a_e and a_d among the table's
  for (int a = 0; a < kAxes; ++a) {
    ie[static_cast<std::size_t>(a)] = indices(a_e_of(a), table.a_e, "a_e");
    id[static_cast<std::size_t>(a)] = indices(a_d_of(a), table.a_d, "a_d");
    for (const auto& [own, coarse] : {std::pair{&a_e_of(a), &a_e}, {&a_d_of(a), &a_d}})
      for (double v : *coarse)
        if (node_index(*own, v) == std::string::npos)
          throw InputError(std::string("skin table offsets: the ") + kAxisNames[a] + " axis' nodes miss the coarse node " + format_number(v));
  }
  if (!(base[0] == table.g && base[1] == table.eta && base[2] == table.dermis_ratio))
    throw InputError("skin table offsets: the base geometry is not the table's");
  // Reused rows: each of these x among the reused table's, and per row its tau, a_e and a_d among
  // the reused file's (an axis' a_e and a_d its own). New tau nodes (the table extended) are
  // solved, the rest copied.
  const std::vector<std::size_t> reuse_x = reuse ? node_indices(reuse->x, x) : std::vector<std::size_t>{};
  const bool same_grid = reuse && std::find(reuse_x.begin(), reuse_x.end(), std::string::npos) == reuse_x.end();
  const std::vector<std::size_t> reuse_t = same_grid ? node_indices(reuse->tau, tau) : std::vector<std::size_t>{};
  auto copy_row = [&](const std::vector<double>& from, std::size_t r_from, std::vector<double>& to, std::size_t r_to) {
    for (std::size_t i = 0; i < n_x; ++i) to[r_to * n_x + i] = from[r_from * reuse->x.size() + reuse_x[i]];
  };
  // The jobs: per (axis, node) the top layers alone (their R(k), which the light from below
  // subtracts, and for g and eta their profiles' offsets), then the light from below; per job
  // k = i_tau * n_e + i_e, or (i_tau * n_e + i_e) * n_d + i_d, on the axis' nodes.
  // (A top job whose row is held solves the top layer for the light from below only: its stored
  // row is kept, as solves of earlier solver versions differ in the row's last decimal.)
  struct Job { int axis; std::size_t node; std::size_t k; bool held = false; };
  std::vector<Job> top_jobs, low_jobs;
  for (int a = 0; a < kAxes; ++a) {
    const auto au = static_cast<std::size_t>(a);
    const std::vector<double>&ae = a_e_of(a), &ad = a_d_of(a);
    const std::size_t n_e = ae.size(), n_d = ad.size();
    d_top[au].assign(nodes[au].size(), {});
    d_low[au].assign(nodes[au].size(), {});
    low_solved[au].assign(nodes[au].size(), 0);
    // The nodes extended (new tau nodes of the table, new a_e or a_d nodes of this axis): a node
    // whose light from below the reused file holds as the difference of two profiles keeps those
    // rows (and that label) and only the new ones are solved.
    const bool extending = same_grid && !(same_nodes(reuse->tau, tau) && same_nodes(reuse->a_e_of(a), ae) && same_nodes(reuse->a_d_of(a), ad));
    for (std::size_t j = 0; j < nodes[au].size(); ++j) {
      if (nodes[au][j] == base[au]) continue;
      if (a != 2) d_top[au][j].assign(n_t * n_e * n_x, 0.0);
      d_low[au][j].assign(n_t * n_e * n_d * n_x, 0.0);
      std::vector<char> held_top(n_t * n_e, 0), held_low(n_t * n_e * n_d, 0);
      const std::size_t r = same_grid ? node_index(reuse->nodes[au], nodes[au][j]) : std::string::npos;
      const bool reused = r != std::string::npos && !reuse->d_low[au][r].empty();
      const bool solved = reused && r < reuse->low_solved[au].size() && reuse->low_solved[au][r];
      // (the rows solved below are the light from below on its own, unless a node held as a
      // difference is extended)
      low_solved[au][j] = reused && !solved && extending ? 0 : 1;
      if (reused) {
        const std::vector<double>&re = reuse->a_e_of(a), &rd = reuse->a_d_of(a);
        const std::vector<std::size_t> reuse_e = node_indices(re, ae), reuse_d = node_indices(rd, ad);
        std::size_t held = 0;
        for (std::size_t i_t = 0; i_t < n_t; ++i_t)
          for (std::size_t i_e = 0; i_e < n_e; ++i_e) {
            const std::size_t e = reuse_e[i_e], t = reuse_t[i_t];
            if (e == std::string::npos || t == std::string::npos) continue;
            if (a != 2) copy_row(reuse->d_top[au][r], t * re.size() + e, d_top[au][j], i_t * n_e + i_e);
            held_top[i_t * n_e + i_e] = 1;
            for (std::size_t i_d = 0; i_d < n_d; ++i_d) {
              const std::size_t d = reuse_d[i_d];
              if (d == std::string::npos) continue;
              copy_row(reuse->d_low[au][r], (t * re.size() + e) * rd.size() + d, d_low[au][j], (i_t * n_e + i_e) * n_d + i_d);
              held_low[(i_t * n_e + i_e) * n_d + i_d] = 1;
              ++held;
            }
          }
        // (a node whose light from below is held as the difference of two profiles is solved
        // again, its top layers with it: their R(k) is what the light from below subtracts;
        // unless the table was extended: then only its new rows are solved, and it keeps its label)
        if (!solved && !extending) {
          std::fill(held_low.begin(), held_low.end(), 0);
          std::fill(held_top.begin(), held_top.end(), 0);
        } else if (held == held_low.size()) {
          continue;  // every row copied
        }
      }
      for (std::size_t k = 0; k < n_t * n_e; ++k) {
        bool needed = !held_top[k];
        for (std::size_t i_d = 0; i_d < n_d; ++i_d) needed = needed || !held_low[k * n_d + i_d];
        if (needed) top_jobs.push_back({a, j, k, held_top[k] != 0});
      }
      for (std::size_t k = 0; k < n_t * n_e * n_d; ++k)
        if (!held_low[k]) low_jobs.push_back({a, j, k});
    }
  }
  std::mutex m;
  std::size_t done = 0;
  const std::size_t total = top_jobs.size() + low_jobs.size();
  auto tick = [&] {
    if (!progress) return;
    const std::lock_guard<std::mutex> lock(m);
    progress(++done, total);
  };
  const std::size_t nx_table = table.x.size();
  auto at_x = [&](const std::vector<double>& fine) {
    std::vector<double> out(n_x);
    for (std::size_t i = 0; i < n_x; ++i) out[i] = fine[ix[i]];
    return out;
  };
  auto row_of = [&](const std::vector<double>& v, std::size_t k) {
    return std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(k * nx_table), v.begin() + static_cast<std::ptrdiff_t>((k + 1) * nx_table));
  };
  // The geometry of an axis node (no nodes or values: the solves read its eta, g, dermis ratio, x).
  auto geometry = [&](int axis, std::size_t node) {
    SkinStackTable geo;
    const double v = nodes[static_cast<std::size_t>(axis)][node];
    geo.g = axis == 0 ? v : table.g;
    geo.eta = axis == 1 ? v : table.eta;
    geo.dermis_ratio = axis == 2 ? v : table.dermis_ratio;
    geo.x = table.x;
    return geo;
  };
  // The top layers alone, solved: per job its R(k), and (g, eta) its profile.
  std::vector<std::vector<double>> tops(top_jobs.size()), tops_k(top_jobs.size());
  tbb::parallel_for(std::size_t{0}, top_jobs.size(), [&](std::size_t q) {
    if (util::cancel::requested()) return;
    const Job& jb = top_jobs[q];
    const auto au = static_cast<std::size_t>(jb.axis);
    const SkinStackTable geo = geometry(jb.axis, jb.node);
    const std::vector<double>& ae = a_e_of(jb.axis);
    const std::size_t n_e = ae.size(), i_t = jb.k / n_e, i_e = jb.k % n_e;
    tops_k[q] = top_frequencies(geo, tau[i_t], ae[i_e]);
    if (jb.axis != 2) {
      const Layer ab = absorber(geo);
      tops[q] = solve(geo, tau[i_t], ae[i_e], &ab);
      if (!jb.held) {
        const std::size_t kt = it[i_t] * table.a_e.size() + ie[au][i_e];
        const std::vector<double> d = top_offset(tops[q], row_of(table.ln_rho_top, kt), at_x);
        std::copy(d.begin(), d.end(), d_top[au][jb.node].begin() + static_cast<std::ptrdiff_t>(jb.k * n_x));
      }
    }
    tick();
  });
  util::cancel::check();
  // Each (axis, node, tau, a_e)'s top job.
  std::map<std::array<std::size_t, 3>, std::size_t> top_of;
  for (std::size_t q = 0; q < top_jobs.size(); ++q)
    top_of[{static_cast<std::size_t>(top_jobs[q].axis), top_jobs[q].node, top_jobs[q].k}] = q;
  tbb::parallel_for(std::size_t{0}, low_jobs.size(), [&](std::size_t q) {
    if (util::cancel::requested()) return;
    const Job& jb = low_jobs[q];
    const auto au = static_cast<std::size_t>(jb.axis);
    const SkinStackTable geo = geometry(jb.axis, jb.node);
    const std::vector<double>&ae = a_e_of(jb.axis), &ad = a_d_of(jb.axis);
    const std::size_t n_e = ae.size(), n_d = ad.size();
    const std::size_t i_d = jb.k % n_d, i_e = (jb.k / n_d) % n_e, i_t = jb.k / (n_d * n_e);
    const std::size_t kt = it[i_t] * table.a_e.size() + ie[au][i_e], k_low = kt * table.a_d.size() + id[au][i_d];
    const std::size_t q_top = top_of.at({au, jb.node, i_t * n_e + i_e});
    const std::vector<double> base_top = row_of(table.ln_rho_top, kt), base_low = row_of(table.ln_rho, k_low);
    // The top layer's profile (the dermis ratio's is the table's).
    std::vector<double> T = tops[q_top];
    if (jb.axis == 2) T = mapped(base_top, [](double v) { return std::exp(v); });
    const std::vector<double> d = low_offset(geo, tau[i_t], ae[i_e], ad[i_d], T, tops_k[q_top], base_top, base_low, at_x);
    std::copy(d.begin(), d.end(), d_low[au][jb.node].begin() + static_cast<std::ptrdiff_t>(jb.k * n_x));
    tick();
  });
  util::cancel::check();
}

namespace {
// The rows of one axis node's offsets (or one corner's cross terms): per (tau, a_e) the top
// layer's row (a_d = inf, when there is one), then per a_d the light from below's, each
// "prefix,tau,a_e,a_d" and the values at x to 3 decimals.
void write_rows(std::ostream& os, const std::string& prefix, const std::vector<double>& tau, const std::vector<double>& a_e,
                const std::vector<double>& a_d, std::size_t n_x, const std::vector<double>& top, const std::vector<double>& low) {
  char buf[32];
  std::size_t k = 0, k_top = 0;
  auto row = [&](double t, double e, const std::string& d, const double* v) {
    os << prefix << ',' << format_number_list({t, e}) << ',' << d;
    for (std::size_t i = 0; i < n_x; ++i) {
      std::snprintf(buf, sizeof buf, ",%.3f", v[i]);
      os << buf;
    }
    os << '\n';
  };
  for (double t : tau)
    for (double e : a_e) {
      if (!top.empty()) row(t, e, "inf", top.data() + k_top++ * n_x);
      for (double d : a_d) row(t, e, format_number(d), low.data() + k++ * n_x);
    }
}
// One list of coarse nodes (`key` in `src`): at least 4, within [1e-9, 1e9] and increasing.
void check_coarse_nodes(const std::vector<double>& v, const std::string& key, const std::string& src) {
  if (v.size() < 4) throw InputError(src + ": '" + key + "' needs at least 4 nodes");
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!(v[i] >= 1e-9 && v[i] <= 1e9) || (i > 0 && !(std::sqrt(v[i]) > std::sqrt(v[i - 1]) && std::log(v[i]) > std::log(v[i - 1]))))
      throw InputError(src + ": '" + key + "' must lie within [1e-9, 1e9] and increase");
}
// The coarse nodes of an offsets or cross-terms file, each checked by check_coarse_nodes.
void read_coarse_nodes(const std::map<std::string, std::string, std::less<>>& meta, const std::string& src, std::vector<double>& tau,
                       std::vector<double>& a_e, std::vector<double>& a_d, std::vector<double>& x) {
  tau = metadata_numbers(meta, "tau", src);
  a_e = metadata_numbers(meta, "a_e", src);
  a_d = metadata_numbers(meta, "a_d", src);
  x = metadata_numbers(meta, "x", src);
  for (const auto& [v, key] : {std::pair{&tau, "tau"}, {&a_e, "a_e"}, {&a_d, "a_d"}, {&x, "x"}}) check_coarse_nodes(*v, key, src);
}
}  // namespace

std::string SkinStackOffsets::to_csv() const {
  std::ostringstream os;
  os << "# Spectral Skin: offsets of the skin table's two parts (data/skin_stack_profiles.csv) for\n"
        "# another g, index or dermis ratio: ln rho(value) - ln rho(table), computed by this project's\n"
        "# frequency-domain transport solver (FrequencyStack) on a coarse subset of the table's nodes;\n"
        "# their use: include/skin/transport/skin_stack_table.hpp, docs/accurate-solver.md sec. 4.\n";
  os << "# provenance: " << provenance << '\n';
  for (int a = 0; a < kAxes; ++a) {
    os << "# " << kAxisNames[a] << ": " << format_number(base[a]) << "\n# " << kAxisNames[a]
       << "_nodes: " << format_number_list(nodes[a]) << '\n';
    std::vector<double> solved;
    for (std::size_t j = 0; j < nodes[a].size() && j < low_solved[a].size(); ++j)
      if (low_solved[a][j]) solved.push_back(nodes[a][j]);
    if (!solved.empty()) os << "# " << kAxisNames[a] << "_low_solved: " << format_number_list(solved) << '\n';
    if (!axis_a_e[static_cast<std::size_t>(a)].empty())
      os << "# " << kAxisNames[a] << "_a_e: " << format_number_list(axis_a_e[static_cast<std::size_t>(a)]) << '\n';
    if (!axis_a_d[static_cast<std::size_t>(a)].empty())
      os << "# " << kAxisNames[a] << "_a_d: " << format_number_list(axis_a_d[static_cast<std::size_t>(a)]) << '\n';
  }
  os << "# tau: " << format_number_list(tau) << "\n# a_e: " << format_number_list(a_e)
     << "\n# a_d: " << format_number_list(a_d) << "\n# x: " << format_number_list(x) << '\n';
  os << "# Per axis and node other than the table's own: per (tau, a_e) the top layer's offset\n"
        "# (a_d = inf; none on the dermis_ratio axis), then per a_d the offset of the light from below\n"
        "# (solved on its own at the nodes AXIS_low_solved names; elsewhere the difference of two profiles);\n"
        "# a_e and a_d are the axis' own nodes where AXIS_a_e or AXIS_a_d names them (finer), else the above.\n";
  os << "axis,value,tau,a_e,a_d";
  for (std::size_t i = 0; i < x.size(); ++i) os << ",d_" << i;
  os << '\n';
  for (int a = 0; a < kAxes; ++a)
    for (std::size_t j = 0; j < nodes[a].size(); ++j)
      if (!d_low[a][j].empty())
        write_rows(os, std::to_string(a) + ',' + format_number(nodes[a][j]), tau, a_e_of(a), a_d_of(a), x.size(), d_top[a][j],
                   d_low[a][j]);
  return os.str();
}

SkinStackOffsets SkinStackOffsets::parse(std::string_view text, std::string_view source) {
  const std::string src(source);
  const auto meta = csv_metadata(text);
  SkinStackOffsets o;
  o.provenance = meta.count("provenance") ? meta.at("provenance") : "";
  for (int a = 0; a < kAxes; ++a) {
    o.base[static_cast<std::size_t>(a)] = metadata_number(meta, kAxisNames[a], src);
    o.nodes[static_cast<std::size_t>(a)] = metadata_numbers(meta, std::string(kAxisNames[a]) + "_nodes", src);
  }
  read_coarse_nodes(meta, src, o.tau, o.a_e, o.a_d, o.x);
  for (int a = 0; a < kAxes; ++a) {
    const auto au = static_cast<std::size_t>(a);
    // An axis' own a_e or a_d nodes: at least 4, within [1e-9, 1e9], increasing, holding the coarse ones.
    for (const auto& [own, coarse, key] : {std::tuple{&o.axis_a_e[au], &o.a_e, "_a_e"}, {&o.axis_a_d[au], &o.a_d, "_a_d"}}) {
      const std::string name = std::string(kAxisNames[a]) + key;
      if (!meta.count(name)) continue;
      *own = metadata_numbers(meta, name, src);
      check_coarse_nodes(*own, name, src);
      for (double v : *coarse)
        if (node_index(*own, v) == std::string::npos)
          throw InputError(src + ": '" + name + "' must hold every node of '" + std::string(key + 1) + "' (" + format_number(v) + " is missing)");
    }
    o.low_solved[au].assign(o.nodes[au].size(), 0);
    const std::string key = std::string(kAxisNames[a]) + "_low_solved";
    if (!meta.count(key)) continue;
    for (double v : metadata_numbers(meta, key, src)) {
      const std::size_t j = node_index(o.nodes[au], v);
      if (j == std::string::npos || v == o.base[au])
        throw InputError(src + ": '" + key + "' names " + format_number(v) + ", which is not one of the '" + kAxisNames[a] +
                         "_nodes' other than the table's " + format_number(o.base[au]));
      o.low_solved[au][j] = 1;
    }
  }
  const double lo[kAxes] = {0.0, 1.0, 1e-3}, hi[kAxes] = {0.99, 3.0, 1e3};
  for (int a = 0; a < kAxes; ++a) {
    const auto& v = o.nodes[static_cast<std::size_t>(a)];
    const double b = o.base[static_cast<std::size_t>(a)];
    if (node_index(v, b) == std::string::npos)
      throw InputError(src + ": '" + kAxisNames[a] + "_nodes' needs the table's " + format_number(b) + " among them");
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!(v[i] >= lo[a] && v[i] <= hi[a]) || (i > 0 && !(v[i] > v[i - 1] * (1 + 1e-9))))
        throw InputError(src + ": '" + kAxisNames[a] + "_nodes' must lie within [" + format_number(lo[a]) + ", " +
                         format_number(hi[a]) + "] and increase");
  }
  const Table data = parse_csv(text, src);
  const std::size_t n_x = o.x.size(), n_t = o.tau.size();
  if (data.columns.size() != 5 + n_x)
    throw InputError(src + ": expected " + std::to_string(5 + n_x) + " columns, found " + std::to_string(data.columns.size()));
  std::size_t r = 0;
  const std::size_t rows = data.rows();
  auto cell = [&](std::size_t c) { return data.data[c][r]; };
  for (int a = 0; a < kAxes; ++a) {
    const auto au = static_cast<std::size_t>(a);
    const std::vector<double>&ae = o.a_e_of(a), &ad = o.a_d_of(a);
    const std::size_t n_e = ae.size(), n_d = ad.size();
    o.d_top[au].assign(o.nodes[au].size(), {});
    o.d_low[au].assign(o.nodes[au].size(), {});
    for (std::size_t j = 0; j < o.nodes[au].size(); ++j) {
      if (o.nodes[au][j] == o.base[au]) continue;
      if (a != 2) o.d_top[au][j].assign(n_t * n_e * n_x, 0.0);
      o.d_low[au][j].assign(n_t * n_e * n_d * n_x, 0.0);
      std::size_t k = 0, k_top = 0;
      for (std::size_t i_t = 0; i_t < n_t; ++i_t)
        for (std::size_t i_e = 0; i_e < n_e; ++i_e)
          for (std::size_t i_d = a == 2 ? 1 : 0; i_d <= n_d; ++i_d) {
            const bool top = i_d == 0;
            if (r >= rows)
              throw InputError(src + ": the file ends before the rows of " + kAxisNames[a] + " = " + format_number(o.nodes[au][j]));
            const double want[5] = {static_cast<double>(a), o.nodes[au][j], o.tau[i_t], ae[i_e], top ? kInfinity : ad[i_d - 1]};
            for (std::size_t c = 0; c < 5; ++c) {
              const double v = cell(c);
              if (!(want[c] == kInfinity ? v == kInfinity : (c == 0 ? v == want[c] : std::abs(v / want[c] - 1) <= 1e-6)))
                throw InputError(src + ": row " + std::to_string(r + 1) + " is not node (axis, value, tau, a_e, a_d) = (" +
                                 std::to_string(a) + ", " + format_number(want[1]) + ", " + format_number(want[2]) + ", " +
                                 format_number(want[3]) + ", " + format_number(want[4]) + ")");
            }
            double* out = top ? o.d_top[au][j].data() + k_top++ * n_x : o.d_low[au][j].data() + k++ * n_x;
            for (std::size_t i = 0; i < n_x; ++i) {
              const double v = cell(5 + i);
              if (!(std::abs(v) <= kMaxOffset))
                throw InputError(src + ": row " + std::to_string(r + 1) + ", column " + data.columns[5 + i] + " = " +
                                 format_number(v) + " is not a finite number within " + format_number(kMaxOffset) + " of 0");
              out[i] = v;
            }
            ++r;
          }
    }
  }
  if (r != rows) throw InputError(src + ": " + std::to_string(rows - r) + " row(s) after its last node");
  return o;
}

namespace {
// The far field of a solved light from below ends in the noise of its inversion: R(k) of the two
// solves carries ~1e-12 of noise (~1e-10 of its value at low k), which leaves rho noisy from ~1e-9
// of the peak of the whole profile (top + low) on. In a node with tau 0.26, a_e 1.01 and a_d 0.78
// the stored row, solved again with 2 and 4 times finer frequencies and a finer quadrature, agrees
// to x 7.5, then differs by 15 % at x 8.7 (~2e-10 of the peak) and changes sign at x 10; read
// between such nodes, a 0.023 mm epidermis was 53-97 % low at 0.61-0.71 mm, 7.3 times what a
// 4e6-photon Monte Carlo allows (docs/accurate-solver.md, sec. 4). There ln rho falls nearly
// linearly in x (the finer solves' slope within 2 % over x 4.2-8.7), so each row is continued that
// way: from kFarFieldWatched of the whole peak on (beyond the row's own peak), the slope of ln rho
// between neighbouring nodes must not steepen faster than it did between the nodes before, by more
// than kFarFieldTolerance of ln rho at one node (flattening is not watched: where a less absorbed
// part of the light takes over, the slope flattens for good); the first node that breaks that ends
// the row's own values, and beyond, ln rho continues with the least-squares slope of the last
// kFarFieldFit of them (no lower than the row's floor, kLowFloor of the whole peak).
constexpr double kFarFieldWatched = 1e-6;
constexpr double kFarFieldTolerance = 0.05;
constexpr std::size_t kFarFieldFit = 3;
// Returns the last node kept (x.size() when none is changed).
std::size_t continue_far_field(const std::vector<double>& x, std::vector<double>& v, double ln_whole_peak) {
  const std::size_t n = x.size();
  const double watched = ln_whole_peak + std::log(kFarFieldWatched);
  const auto peak = static_cast<std::size_t>(std::max_element(v.begin(), v.end()) - v.begin());
  std::size_t i0 = std::max<std::size_t>(peak, 1);
  while (i0 < n && v[i0] >= watched) ++i0;
  if (i0 + 2 >= n) return n;
  // the slope between node i and i + 1, and its change from the one before
  auto slope = [&](std::size_t i) { return (v[i + 1] - v[i]) / (x[i + 1] - x[i]); };
  auto change = [&](std::size_t i) { return slope(i) - slope(i - 1); };
  std::size_t last = n;
  for (std::size_t i = i0; i + 1 < n; ++i) {
    // A change of ln rho by e at node i + 1 changes slope(i) by e / (x[i+1] - x[i]); counting
    // the node before it, the change by up to twice that.
    const double c = change(i), tol = 2 * kFarFieldTolerance / (x[i + 1] - x[i]);
    const double before = i > i0 ? change(i - 1) : c;
    if (c < std::min(before, 0.0) - tol) {  // steepening faster than before
      last = i;
      break;
    }
  }
  if (last == n) return n;
  const std::size_t first = last >= peak + kFarFieldFit ? last + 1 - kFarFieldFit : peak;
  if (first == last) return n;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = first; i <= last; ++i) {
    sx += x[i];
    sy += v[i];
    sxx += x[i] * x[i];
    sxy += x[i] * v[i];
  }
  const double m = static_cast<double>(last - first + 1);
  const double fitted = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  if (!(fitted < 0)) return n;  // (not falling there: left as it is)
  // (down to the rows' floor, as solved rows: a row far below its neighbours bends their
  // interpolation)
  const double lowest = ln_whole_peak + std::log(kLowFloor);
  for (std::size_t i = last + 1; i < n; ++i) v[i] = std::max(v[last] + fitted * (x[i] - x[last]), lowest);
  return last;
}
// The peak of ln(e^top + e^low) over two rows of n values.
double ln_whole_peak(const double* top, const double* low, std::size_t n) {
  // (only where the larger part is within ln 2 of the largest can the sum be largest)
  double larger = -1e300, peak = -1e300;
  for (std::size_t i = 0; i < n; ++i) larger = std::max(larger, std::max(top[i], low[i]));
  for (std::size_t i = 0; i < n; ++i)
    if (std::max(top[i], low[i]) >= larger - std::numbers::ln2) peak = std::max(peak, log_sum(top[i], low[i]));
  return peak;
}
}  // namespace

namespace {
// The table's lights from below (ln_rho, rows of x) continued beyond their noise, in place; per
// row the last node kept (x.size() where none is changed).
std::vector<std::size_t> continue_lows(const SkinStackTable& t, std::vector<double>& ln_rho) {
  const std::size_t n_x = t.x.size(), n_d = t.a_d.size();
  std::vector<std::size_t> kept(t.tau.size() * t.a_e.size() * n_d);
  std::vector<double> row(n_x);
  for (std::size_t k = 0; k < kept.size(); ++k) {
    double* low = ln_rho.data() + k * n_x;
    std::copy_n(low, n_x, row.begin());
    kept[k] = continue_far_field(t.x, row, ln_whole_peak(t.ln_rho_top.data() + (k / n_d) * n_x, low, n_x));
    std::copy_n(row.begin(), n_x, low);
  }
  return kept;
}
}  // namespace

void SkinStackTable::settle() { continue_lows(*this, ln_rho); }

namespace {
// Where the light from below is under kReliableLow of the top layer's at a node, its part is the
// difference of two solves of nearly the same value, and the offset of that difference is noise
// (seen: 0.5 off the solver's in a bloody dermis at x 2-3): there each row of `rows` (laid out as
// d_low on the coarse nodes tau, a_e, a_d and every stride-th x of the table's) holds its value
// from the nearest x where the part is reliable (in a row reliable nowhere, from where it is
// largest against the top layer's).
void hold_unreliable_low(const SkinStackTable& table, const std::vector<double>& tau, const std::vector<double>& a_e,
                         const std::vector<double>& a_d, std::size_t n_x, std::vector<double>& rows) {
  constexpr double kReliableLow = 0.05;
  if (rows.empty()) return;
  const std::size_t n_e = a_e.size(), n_d = a_d.size(), nx_t = table.x.size();
  const std::size_t stride = (nx_t - 1) / (n_x - 1);
  std::vector<std::size_t> it, ie, id;
  for (double v : tau) it.push_back(node_index(table.tau, v));
  for (double v : a_e) ie.push_back(node_index(table.a_e, v));
  for (double v : a_d) id.push_back(node_index(table.a_d, v));
  for (std::size_t k = 0; k < tau.size() * n_e * n_d; ++k) {
    const std::size_t i_d = k % n_d, i_e = (k / n_d) % n_e, i_t = k / (n_d * n_e);
    const std::size_t kt = it[i_t] * table.a_e.size() + ie[i_e], k_low = kt * table.a_d.size() + id[i_d];
    std::vector<char> ok(n_x);
    std::size_t best = 0;
    double best_q = -1e300;
    bool any = false;
    for (std::size_t i = 0; i < n_x; ++i) {
      const double q = table.ln_rho[k_low * nx_t + stride * i] - table.ln_rho_top[kt * nx_t + stride * i];
      ok[i] = q >= std::log(kReliableLow);
      any = any || ok[i];
      if (q > best_q) { best_q = q; best = i; }
    }
    if (!any) ok[best] = 1;
    hold_where_not(rows.data() + k * n_x, ok);
  }
}
}  // namespace

void SkinStackOffsets::settle(const SkinStackTable& table) {
  // Only the nodes whose light from below is the difference of two profiles: where it is solved
  // on its own it is smooth near the beam too, and holding it there costs accuracy (asian skin
  // with the dermis twice as scattering at 500 nm: 1.7 % off the solver held, 0.3 % not).
  for (std::size_t a = 0; a < d_low.size(); ++a)
    for (std::size_t j = 0; j < d_low[a].size(); ++j)
      if (!(j < low_solved[a].size() && low_solved[a][j]))
        hold_unreliable_low(table, tau, a_e_of(static_cast<int>(a)), a_d_of(static_cast<int>(a)), x.size(), d_low[a][j]);
  // Each node's light from below (the table's plus the offset) continued beyond its far field's
  // noise, and so is the table's own (SkinStackTable::settle(), after this): the offset becomes the
  // difference of the two continued rows.
  const std::size_t n_x = x.size(), nx_t = table.x.size(), stride = (nx_t - 1) / (n_x - 1);
  std::vector<double> continued = table.ln_rho;  // the table's rows as settle() leaves them
  const std::vector<std::size_t> kept = continue_lows(table, continued);
  std::vector<double> node(n_x), node_top(n_x);
  for (std::size_t a = 0; a < d_low.size(); ++a) {
    const auto& ae = a_e_of(static_cast<int>(a));
    const auto& ad = a_d_of(static_cast<int>(a));
    std::vector<std::size_t> it, ie, id;  // the axis' nodes among the table's
    for (double v : tau) it.push_back(node_index(table.tau, v));
    for (double v : ae) ie.push_back(node_index(table.a_e, v));
    for (double v : ad) id.push_back(node_index(table.a_d, v));
    for (std::size_t j = 0; j < d_low[a].size(); ++j) {
      auto& rows = d_low[a][j];
      if (rows.empty()) continue;
      const bool has_top = j < d_top[a].size() && !d_top[a][j].empty();
      const bool solved_alone = j < low_solved[a].size() && low_solved[a][j];
      for (std::size_t k = 0; k < tau.size() * ae.size() * ad.size(); ++k) {
        const std::size_t i_d = k % ad.size(), i_e = (k / ad.size()) % ae.size(), i_t = k / (ad.size() * ae.size());
        const std::size_t k_top = it[i_t] * table.a_e.size() + ie[i_e], k_low = k_top * table.a_d.size() + id[i_d];
        const double* top = table.ln_rho_top.data() + k_top * nx_t;
        const double *solved = table.ln_rho.data() + k_low * nx_t, *settled = continued.data() + k_low * nx_t;
        double* d = rows.data() + k * n_x;
        if (!solved_alone) {
          // (a node's light from below as the difference of two profiles, held where unreliable:
          // the offset is held beyond the table's row too)
          for (std::size_t i = kept[k_low] / stride + 1; i < n_x; ++i) d[i] = d[kept[k_low] / stride];
          continue;
        }
        const double* dt = has_top ? d_top[a][j].data() + (k / ad.size()) * n_x : nullptr;
        for (std::size_t i = 0; i < n_x; ++i) {
          node[i] = solved[stride * i] + d[i];
          node_top[i] = top[stride * i] + (dt ? dt[i] : 0.0);
        }
        continue_far_field(x, node, ln_whole_peak(node_top.data(), node.data(), n_x));
        for (std::size_t i = 0; i < n_x; ++i) d[i] = std::clamp(node[i] - settled[stride * i], -kMaxOffset, kMaxOffset);
      }
    }
  }
}

std::string SkinStackOffsets::gap(double g_v, double eta_v, double ratio_v) const {
  const double v[kAxes] = {g_v, eta_v, ratio_v};
  // g and the index are added alone (together they stay within 0.3-6.4 % of the solver, median
  // 0.9 %, above 1e-4 of R(0.02 mm) over 10 random skins). Another dermis ratio with another g or
  // index needs the cross terms (the offsets added alone: 0.3-7.6 % over 20 random skins, 3 above
  // 5 %, and 2 of 25 domain draws read that way beyond 5 % + 3 SE of the Monte Carlo;
  // docs/accurate-solver.md, sec. 4).
  if (!cross && ratio_v != base[2] && (g_v != base[0] || eta_v != base[1]))
    return "another dermis scattering ratio together with another g or index (without cross terms the "
           "skin table's offsets do not combine them)";
  auto name = [](int a) { return std::string(a == 0 ? "g" : a == 1 ? "index" : "the lower layer's sigma_s' / the top layer's"); };
  for (int a = 0; a < kAxes; ++a) {
    const auto& n = nodes[static_cast<std::size_t>(a)];
    const double top = a == 0 ? g_reach(n) : n.back();
    // (a relative 1e-9 beyond an end: a ratio of two coefficients computed apart)
    if (!(v[a] >= n.front() * (1 - 1e-9) && v[a] <= top * (1 + 1e-9)))
      return name(a) + " " + format_number(v[a]) + " is outside the skin table's [" + format_number(n.front()) + ", " +
             format_number(std::round(top * 1e4) / 1e4) + "]";
  }
  // Combined with another dermis ratio, g and the index stop where the cross terms reach: their
  // corners, or on a side without corners the other side's continued through the base, no farther
  // than that corner is from the base (an axis' offsets may reach farther).
  if (cross && ratio_v != base[2])
    for (int a = 0; a < 2; ++a) {
      const double lo = cross->reach(a, 0);
      double hi = cross->reach(a, 1);
      // (g continued beyond its last node as far as the offsets are, where the cross terms have
      // corners to continue: their position continues linearly too)
      if (a == 0 && hi > base[0]) hi = std::max(hi, g_reach(nodes[0]));
      if (!(v[a] >= lo * (1 - 1e-9) && v[a] <= hi * (1 + 1e-9)))
        return name(a) + " " + format_number(v[a]) + " together with another dermis scattering ratio is outside the skin "
               "table's cross terms' reach [" + format_number(std::round(lo * 1e4) / 1e4) + ", " +
               format_number(std::round(hi * 1e4) / 1e4) + "]";
    }
  return {};
}

namespace {
// The solver's floor: a row of the table is noise below about this much of its peak (measured:
// the row of tau 0.395, a_e 0.4, a_d 0.126 within 0.02 in ln rho of a solve of today's solver at
// 1e-8 of its peak, 0.14 off at 3e-9, 0.7 at 1e-9).
constexpr double kSolverFloor = 1e-9;
// The dermis ratio's far field. Its offsets are node solves less the table's rows at their coarse
// tau, a_e and a_d nodes, added to the table's read: the read is the node solves' interpolation
// plus c, the table's read less its rows' interpolation on those coarse nodes. Where those rows
// are near kSolverFloor, c is their noise, and the ratio's offset lifts it into view: a dermis less
// scattering than the table's falls more slowly, several e-folds above the table's rows there
// (ratio 0.2, s 20 /mm, a_d 0.071, between the nodes 0.04 and 0.126: the offset 0.16 short at
// x 24 and 0.5 at x 32, the read 0.64 of the solver's at 1.5 mm; with c left out there, 0.96-1.02
// out to 1.5 mm). So c is kept where the estimate of its noise (each row's weight times
// kSolverFloor over its value against its own peak: a light from below solved on its own is good
// below a dark top layer's peak) is under kFineTrusted, left out above kFineDropped, and in
// between in part, linearly in ln of that estimate. (Against the whole peak instead, c went
// under dark top layers too, whose a_e beyond the offsets' last node only the table follows.)
constexpr double kFineTrusted = 0.01, kFineDropped = 0.1;

// The dermis ratio's offsets `dl` (at o's x) at (t, ae, ad), whose table read is `low`, with c
// left out where the table's rows are near their floor (above).
void fade_ratio_far_field(const SkinStackOffsets& o, const SkinStackTable& table, double t, double ae, double ad,
                          const std::vector<double>& low, std::vector<double>& dl) {
  const std::vector<double>& tau = o.tau;
  const std::size_t n_x = o.x.size(), nx_t = table.x.size(), stride = (nx_t - 1) / (n_x - 1);
  const std::vector<double>&ae_n = o.a_e_of(2), &ad_n = o.a_d_of(2);
  // (Beyond the last a_e or tau node the node solves are held there, and only c follows the skin.)
  if (ae > ae_n.back() || t > tau.back()) return;
  // (the stencils of add()'s light from below on this axis)
  const Lagrange4Stencil st = tau_stencil_held(tau, t, false);
  const Lagrange4Stencil se = a_e_stencil_held(ae_n, ae);
  const Lagrange4Stencil sd = lagrange4_stencil(mapped(ad_n, sqrt_of), std::sqrt(ad));
  std::vector<double> coarse(n_x, 0.0), noise(n_x, 0.0);
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t e = 0; e < 4; ++e)
      for (std::size_t l = 0; l < 4; ++l) {
        const double w = st.weights[i] * se.weights[e] * sd.weights[l];
        if (w == 0) continue;
        const std::size_t kt = node_index(table.tau, tau[st.first + i]) * table.a_e.size() + node_index(table.a_e, ae_n[se.first + e]);
        const std::size_t kl = kt * table.a_d.size() + node_index(table.a_d, ad_n[sd.first + l]);
        const double* low_row = table.ln_rho.data() + kl * nx_t;
        const double peak = *std::max_element(low_row, low_row + nx_t);
        for (std::size_t m = 0; m < n_x; ++m) {
          coarse[m] += w * low_row[stride * m];
          noise[m] += std::abs(w) * kSolverFloor * std::exp(std::min(peak - low_row[stride * m], 700.0));
        }
      }
  for (std::size_t m = 0; m < n_x; ++m) {
    const double c = low[stride * m] - coarse[m];
    const double kept = std::clamp(std::log(kFineDropped / noise[m]) / std::log(kFineDropped / kFineTrusted), 0.0, 1.0);
    dl[m] -= (1 - kept) * c;
  }
}

// Another g or index with another dermis ratio: beyond where the table's read light from below
// is under kCombinedHeld of its whole peak, their offsets and cross terms hold their value. There
// the offsets (differences of solves at the table's ratio, near kSolverFloor) are noise, which the
// ratio's offset lifts into view; the far field's decay is the dermis' own, set by its reduced
// coefficients (the index does not enter it; g barely, by similarity), so an offset of g or the
// index there is one of amplitude. (Measured on the 476 nm skin below SkinStackTable::gap()'s
// kMirrored*: g 0.97 read 0.31 of the solver at x 30, 1.01 held.)
constexpr double kCombinedHeld = 1e-8;
}  // namespace

void SkinStackOffsets::add(double t, double ae, double ad, double g_v, double eta_v, double ratio_v,
                           const SkinStackTable& table, std::vector<double>& top, std::vector<double>& low,
                           bool with_cross) const {
  const std::vector<double>& table_x = table.x;
  const std::size_t n_x = x.size();
  const Lagrange4Stencil st_top = tau_stencil_held(tau, t, true);
  const Lagrange4Stencil st = tau_stencil_held(tau, t, false);
  std::vector<double> dt(n_x, 0.0), dl(n_x, 0.0), dl_r(n_x, 0.0);
  const double v[kAxes] = {g_v, eta_v, ratio_v};
  for (int a = 0; a < kAxes; ++a) {
    const auto au = static_cast<std::size_t>(a);
    if (v[a] == base[au]) continue;
    const std::size_t n_e = a_e_of(a).size(), n_d = a_d_of(a).size();
    const Lagrange4Stencil se = a_e_stencil_held(a_e_of(a), ae);
    const Lagrange4Stencil sd = lagrange4_stencil(mapped(a_d_of(a), sqrt_of), std::sqrt(ad));
    // The axis' nodes and weights: the node itself where v is one, else 4-point Lagrange (linear
    // between two nodes on an axis of fewer than 4).
    const std::vector<double> vars = axis_variables(a, nodes[au]);
    const double u = axis_variable(a, v[a]);
    Lagrange4Stencil sp;
    const std::size_t hit = node_index(nodes[au], v[a]);
    if (hit != std::string::npos) {
      sp.first = a == 0 ? nodes[au].size() - 1 - hit : hit;
      sp.weights = {1, 0, 0, 0};
    } else if (a == 0 && v[a] > nodes[au].back()) {  // beyond the last g node: linear in 1 - g (g_reach)
      const std::size_t n = nodes[au].size();
      const double f = ((1 - v[a]) - (1 - nodes[au][n - 1])) / ((1 - nodes[au][n - 2]) - (1 - nodes[au][n - 1]));
      sp.first = 0;  // (vars reversed: the last node first)
      sp.weights = {1 - f, f, 0, 0};
    } else if (vars.size() >= 4) {
      sp = lagrange4_stencil(vars, u);
    } else {
      const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(std::upper_bound(vars.begin(), vars.end(), u) - vars.begin()), vars.size() - 1);
      sp.first = i - 1;
      const double f = (u - vars[i - 1]) / (vars[i] - vars[i - 1]);
      sp.weights = {1 - f, f, 0, 0};
    }
    for (std::size_t p = 0; p < 4; ++p) {
      if (sp.weights[p] == 0) continue;
      const std::size_t j = a == 0 ? nodes[au].size() - 1 - (sp.first + p) : sp.first + p;
      const double wp = sp.weights[p];
      if (d_low[au][j].empty() || wp == 0) continue;  // the base: no offset
      for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t e = 0; e < 4; ++e) {
          if (!d_top[au][j].empty()) {
            const double w = wp * st_top.weights[i] * se.weights[e];
            const double* r = d_top[au][j].data() + ((st_top.first + i) * n_e + se.first + e) * n_x;
            for (std::size_t m = 0; m < n_x; ++m) dt[m] += w * r[m];
          }
          for (std::size_t l = 0; l < 4; ++l) {
            const double w = wp * st.weights[i] * se.weights[e] * sd.weights[l];
            const double* r = d_low[au][j].data() + (((st.first + i) * n_e + se.first + e) * n_d + sd.first + l) * n_x;
            std::vector<double>& into = a == 2 ? dl_r : dl;
            for (std::size_t m = 0; m < n_x; ++m) into[m] += w * r[m];
          }
        }
    }
  }
  if (with_cross && cross) cross->add(t, ae, ad, {g_v, eta_v, ratio_v}, dt, dl);
  if (with_cross && v[2] != base[2]) {
    if (v[0] != base[0] || v[1] != base[1]) {
      const std::size_t stride = (table_x.size() - 1) / (n_x - 1);
      const double held_below = ln_whole_peak(top.data(), low.data(), table_x.size()) + std::log(kCombinedHeld);
      const auto peak_at = static_cast<std::size_t>(std::max_element(low.begin(), low.end()) - low.begin()) / stride;
      for (std::size_t m = peak_at + 1; m < n_x; ++m)
        if (low[stride * m] < held_below) {
          std::fill(dl.begin() + static_cast<std::ptrdiff_t>(m), dl.end(), dl[m - 1]);
          break;
        }
    }
    fade_ratio_far_field(*this, table, t, ae, ad, low, dl_r);
  }
  for (std::size_t m = 0; m < n_x; ++m) dl[m] += dl_r[m];
  // This table's x are every stride-th of the table's (ln x even): the others by cubic Lagrange
  // in the index.
  const std::size_t stride = (table_x.size() - 1) / (n_x - 1);
  for (std::size_t i = 0; i < table_x.size(); ++i) {
    double ot, ol;
    if (i % stride == 0) {
      ot = dt[i / stride];
      ol = dl[i / stride];
    } else {
      const std::size_t c = i / stride;  // between c and c + 1
      const std::size_t f = std::min(c > 0 ? c - 1 : 0, n_x - 4);
      const std::array<double, 4> w =
          lagrange4_weights(static_cast<double>(i) / static_cast<double>(stride) - static_cast<double>(f));
      ot = ol = 0;
      for (std::size_t q = 0; q < 4; ++q) {
        ot += w[q] * dt[f + q];
        ol += w[q] * dl[f + q];
      }
    }
    top[i] += ot;
    low[i] += ol;
  }
}

// --- Cross terms of two axes ------------------------------------------------------------------

namespace {
const char* const kCrossPairNames[SkinStackCross::kPairs] = {"g x eta", "g x dermis_ratio", "eta x dermis_ratio"};
}  // namespace

void SkinStackCross::settle(const SkinStackTable& table, const SkinStackOffsets& offsets) {
  if (!(same_nodes(tau, offsets.tau) && same_nodes(a_e, offsets.a_e) && same_nodes(a_d, offsets.a_d) && same_nodes(x, offsets.x) &&
        base == offsets.base))
    throw std::logic_error("skin table cross terms: not on the offsets' nodes");
  const double lv = std::log(kCrossValid);
  const std::size_t n_t = tau.size(), n_e = a_e.size(), n_d = a_d.size(), n_x = x.size(), nx_t = table.x.size();
  const std::size_t stride = (nx_t - 1) / (n_x - 1);
  std::vector<std::size_t> it, ie, id;
  for (double v : tau) it.push_back(node_index(table.tau, v));
  for (double v : a_e) ie.push_back(node_index(table.a_e, v));
  for (double v : a_d) id.push_back(node_index(table.a_d, v));
  // Holds row outside the first run of ok x (0 where there is none).
  auto hold = [&](double* row, const std::vector<char>& ok) {
    std::size_t f = 0;
    while (f < n_x && !ok[f]) ++f;
    if (f == n_x) { std::fill(row, row + n_x, 0.0); return; }
    std::size_t l = f;
    while (l + 1 < n_x && ok[l + 1]) ++l;
    for (std::size_t i = 0; i < f; ++i) row[i] = row[f];
    for (std::size_t i = l + 1; i < n_x; ++i) row[i] = row[l];
  };
  // A row of terms (at node `first` / n_x of its part) against the table's part at that node
  // (table_part, every stride-th x) and the two axes' offsets there (empty: none): the corner's part is
  // their sum.
  std::vector<char> ok(n_x);
  auto settle_row = [&](double* row, const double* table_part, const std::vector<double>& oa, std::size_t first_a,
                        const std::vector<double>& ob, std::size_t first_b, double floor) {
    for (std::size_t i = 0; i < n_x; ++i) {
      const double b = table_part[stride * i];
      const double corner = b + (oa.empty() ? 0.0 : oa[first_a + i]) + (ob.empty() ? 0.0 : ob[first_b + i]) + row[i];
      ok[i] = b > floor && corner > floor;
    }
    hold(row, ok);
  };
  for (std::size_t p = 0; p < kPairs; ++p)
    for (std::size_t c = 0; c < 4; ++c) {
      const std::size_t a = static_cast<std::size_t>(kPairAxes[p][0]), b = static_cast<std::size_t>(kPairAxes[p][1]);
      const double va = ends[a][c / 2], vb = ends[b][c % 2];
      if (va == base[a] || vb == base[b] || c_low[p][c].empty()) continue;
      const std::size_t ja = node_index(offsets.nodes[a], va), jb = node_index(offsets.nodes[b], vb);
      if (ja == std::string::npos || jb == std::string::npos) throw std::logic_error("skin table cross terms: an end is not an offsets node");
      for (std::size_t k = 0; k < n_t * n_e; ++k) {
        const std::size_t kt = it[k / n_e] * table.a_e.size() + ie[k % n_e];
        const double* bt = table.ln_rho_top.data() + kt * nx_t;
        for (std::size_t l = 0; l < n_d; ++l) {
          const double* bl = table.ln_rho.data() + (kt * table.a_d.size() + id[l]) * nx_t;
          double peak = -std::numeric_limits<double>::infinity();
          for (std::size_t i = 0; i < nx_t; ++i) peak = std::max(peak, log_sum(bt[i], bl[i]));
          // (each axis' offsets on its own nodes, which hold these)
          const std::size_t kl = k * n_d + l, i_t = k / n_e, i_e = k % n_e;
          const int ia = static_cast<int>(a), ib = static_cast<int>(b);
          settle_row(c_low[p][c].data() + kl * n_x, bl, offsets.d_low[a][ja], offsets.low_row(ia, i_t, i_e, l) * n_x,
                     offsets.d_low[b][jb], offsets.low_row(ib, i_t, i_e, l) * n_x, peak + lv);
          if (l == 0 && !c_top[p][c].empty())
            settle_row(c_top[p][c].data() + k * n_x, bt, offsets.d_top[a][ja], offsets.top_row(ia, i_t, i_e) * n_x,
                       offsets.d_top[b][jb], offsets.top_row(ib, i_t, i_e) * n_x, peak + lv);
        }
      }
    }
}

void SkinStackCross::rebase(const SkinStackOffsets& from, const SkinStackOffsets& to) {
  for (const SkinStackOffsets* o : {&from, &to})
    if (!(same_nodes(tau, o->tau) && same_nodes(a_e, o->a_e) && same_nodes(a_d, o->a_d) && same_nodes(x, o->x) && base == o->base))
      throw std::logic_error("skin table cross terms: not on the offsets' nodes");
  const std::size_t n_t = tau.size(), n_e = a_e.size(), n_d = a_d.size(), n_x = x.size();
  // row += from's two offsets - to's, each axis' on its own nodes at the end `v` (none: 0)
  // (Within kMaxOffset of 0, as every term is computed and parsed. Rebased onto the g and index
  // nodes solved again on 2026-12-06, 127 rows reached beyond it, all where the table's light from
  // below is under kCrossValid of the peak: settle() holds the terms there.)
  auto clamp_offsets = [](double* row, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) row[i] = std::clamp(row[i], -kMaxOffset, kMaxOffset);
  };
  auto shift = [&](double* row, int axis, double v, bool top, std::size_t i_t, std::size_t i_e, std::size_t i_d) {
    const auto au = static_cast<std::size_t>(axis);
    for (const auto& [o, sign] : {std::pair{&from, 1.0}, {&to, -1.0}}) {
      const std::size_t j = node_index(o->nodes[au], v);
      if (j == std::string::npos) throw std::logic_error("skin table cross terms: an end is not an offsets node");
      const std::vector<double>& rows = top ? o->d_top[au][j] : o->d_low[au][j];
      if (rows.empty()) continue;
      const double* d = rows.data() + (top ? o->top_row(axis, i_t, i_e) : o->low_row(axis, i_t, i_e, i_d)) * n_x;
      for (std::size_t i = 0; i < n_x; ++i) row[i] += sign * d[i];
    }
  };
  for (std::size_t p = 0; p < kPairs; ++p)
    for (std::size_t c = 0; c < 4; ++c) {
      const int a = kPairAxes[p][0], b = kPairAxes[p][1];
      const double va = ends[static_cast<std::size_t>(a)][c / 2], vb = ends[static_cast<std::size_t>(b)][c % 2];
      if (va == base[static_cast<std::size_t>(a)] || vb == base[static_cast<std::size_t>(b)] || c_low[p][c].empty()) continue;
      for (std::size_t k = 0; k < n_t * n_e; ++k) {
        const std::size_t i_t = k / n_e, i_e = k % n_e;
        for (std::size_t l = 0; l < n_d; ++l) {
          double* row = c_low[p][c].data() + (k * n_d + l) * n_x;
          for (const auto& [axis, v] : {std::pair{a, va}, {b, vb}}) shift(row, axis, v, false, i_t, i_e, l);
          clamp_offsets(row, n_x);
        }
        if (!c_top[p][c].empty()) {
          double* row = c_top[p][c].data() + k * n_x;
          for (const auto& [axis, v] : {std::pair{a, va}, {b, vb}}) shift(row, axis, v, true, i_t, i_e, 0);
          clamp_offsets(row, n_x);
        }
      }
    }
}

SkinStackCross SkinStackCross::default_nodes(const SkinStackOffsets& offsets) {
  SkinStackCross c;
  c.base = offsets.base;
  for (std::size_t a = 0; a < SkinStackOffsets::kAxes; ++a) c.ends[a] = {offsets.nodes[a].front(), offsets.nodes[a].back()};
  // The offsets' own nodes: on every other of them (2026-12-05) the terms varied too fast between
  // nodes, and the offsets they correct are themselves not smooth everywhere (docs/accurate-solver.md,
  // sec. 4); on the same nodes the two add up to the corner's solve at each node.
  c.tau = offsets.tau;
  c.a_e = offsets.a_e;
  c.a_d = offsets.a_d;
  c.x = offsets.x;
  return c;
}

void SkinStackCross::compute(const SkinStackTable& table, const ProgressCallback& progress, const SkinStackCross* reuse,
                             const std::array<bool, kPairs>* solve_pairs) {
  if (!table.offsets) throw InputError("skin table cross terms: the table has no offsets");
  const SkinStackOffsets& off = *table.offsets;
  const std::size_t n_t = tau.size(), n_e = a_e.size(), n_d = a_d.size(), n_x = x.size(), nx_t = table.x.size();
  if (n_x < 2 || (nx_t - 1) % (n_x - 1) != 0) throw InputError("skin table cross terms: x is not every k-th of the table's");
  const std::size_t stride = (nx_t - 1) / (n_x - 1);
  for (std::size_t i = 0; i < n_x; ++i)
    if (!same_node(x[i], table.x[stride * i])) throw InputError("skin table cross terms: x is not every k-th of the table's");
  // The geometry of a corner.
  auto values = [&](int p, int corner) {
    std::array<double, SkinStackOffsets::kAxes> v = base;
    const auto [a, b] = kPairAxes[static_cast<std::size_t>(p)];
    v[static_cast<std::size_t>(a)] = ends[static_cast<std::size_t>(a)][static_cast<std::size_t>(corner / 2)];
    v[static_cast<std::size_t>(b)] = ends[static_cast<std::size_t>(b)][static_cast<std::size_t>(corner % 2)];
    return v;
  };
  auto geometry = [&](const std::array<double, SkinStackOffsets::kAxes>& v) {
    SkinStackTable geo;
    geo.g = v[0];
    geo.eta = v[1];
    geo.dermis_ratio = v[2];
    geo.x = table.x;
    return geo;
  };
  // The table's parts with both axes' offsets (no cross terms), at this x.
  auto predicted = [&](const std::array<double, SkinStackOffsets::kAxes>& v, double t, double e, double d,
                       std::vector<double>& top, std::vector<double>& low) {
    table.ln_parts_at(t, e, d, top, low);
    off.add(t, e, d, v[0], v[1], v[2], table, top, low, false);
  };
  auto coarse = [&](const std::vector<double>& fine) {
    std::vector<double> out(n_x);
    for (std::size_t i = 0; i < n_x; ++i) out[i] = fine[stride * i];
    return out;
  };
  // A top job whose pair-0 top row is held (copied from `reuse`) keeps it; it is solved only for
  // the light from below.
  struct Job { int pair, corner; std::size_t k; bool held = false; };
  std::vector<Job> top_jobs, low_jobs;
  // Top jobs by their top layer's (g, eta) and (tau, a_e) node, and the (pair, corner, node)s that
  // use another corner's.
  std::map<std::pair<std::array<double, 2>, std::size_t>, std::size_t> top_shared;
  std::map<std::array<std::size_t, 3>, std::size_t> top_alias;
  // Corners neither solved nor held from `reuse`.
  std::vector<std::array<int, 2>> unsolved;
  // Per tau, a_e and a_d node, its index among the reused file's (new nodes, the offsets extended,
  // are solved).
  const bool reusable = reuse && reuse->base == base && same_nodes(reuse->x, x);
  std::vector<std::size_t> reuse_t, reuse_e, reuse_d;
  if (reusable) {
    reuse_t = node_indices(reuse->tau, tau);
    reuse_e = node_indices(reuse->a_e, a_e);
    reuse_d = node_indices(reuse->a_d, a_d);
  }
  for (int p = 0; p < kPairs; ++p)
    for (int c = 0; c < 4; ++c) {
      const auto pu = static_cast<std::size_t>(p), cu = static_cast<std::size_t>(c);
      c_top[pu][cu].assign(p == 0 ? n_t * n_e * n_x : 0, 0.0);
      c_low[pu][cu].assign(n_t * n_e * n_d * n_x, 0.0);
      const auto v = values(p, c);
      if (v[static_cast<std::size_t>(kPairAxes[pu][0])] == base[static_cast<std::size_t>(kPairAxes[pu][0])] ||
          v[static_cast<std::size_t>(kPairAxes[pu][1])] == base[static_cast<std::size_t>(kPairAxes[pu][1])])
        continue;  // an axis without nodes on that side: no term
      const bool solve = !solve_pairs || (*solve_pairs)[pu];
      // The corner's rows copied from `reuse`: (tau, a_e) top rows and (tau, a_e, a_d) rows.
      std::vector<char> ht(n_t * n_e, 0), hl(n_t * n_e * n_d, 0);
      if (reusable) {
        const std::size_t rn_t = reuse->tau.size(), rn_e = reuse->a_e.size(), rn_d = reuse->a_d.size();
        for (int rc = 0; rc < 4; ++rc) {
          const std::size_t a = static_cast<std::size_t>(kPairAxes[pu][0]), b = static_cast<std::size_t>(kPairAxes[pu][1]);
          const auto rcu = static_cast<std::size_t>(rc);
          const bool same = same_node(reuse->ends[a][rcu / 2], v[a]) && same_node(reuse->ends[b][rcu % 2], v[b]) &&
                            !(reuse->ends[a][rcu / 2] == reuse->base[a] || reuse->ends[b][rcu % 2] == reuse->base[b]) &&
                            reuse->c_low[pu][rcu].size() == rn_t * rn_e * rn_d * n_x &&
                            reuse->c_top[pu][rcu].size() == (p == 0 ? rn_t * rn_e * n_x : 0);
          if (!same) continue;
          for (std::size_t i_t = 0; i_t < n_t; ++i_t)
            for (std::size_t i_e = 0; i_e < n_e; ++i_e) {
              const std::size_t t = reuse_t[i_t], e = reuse_e[i_e];
              if (t == std::string::npos || e == std::string::npos) continue;
              const std::size_t k = i_t * n_e + i_e, rk = t * rn_e + e;
              if (p == 0) {
                std::copy_n(reuse->c_top[pu][rcu].begin() + static_cast<std::ptrdiff_t>(rk * n_x), n_x,
                            c_top[pu][cu].begin() + static_cast<std::ptrdiff_t>(k * n_x));
                ht[k] = 1;
              }
              for (std::size_t i_d = 0; i_d < n_d; ++i_d) {
                if (reuse_d[i_d] == std::string::npos) continue;
                std::copy_n(reuse->c_low[pu][rcu].begin() + static_cast<std::ptrdiff_t>((rk * rn_d + reuse_d[i_d]) * n_x), n_x,
                            c_low[pu][cu].begin() + static_cast<std::ptrdiff_t>((k * n_d + i_d) * n_x));
                hl[k * n_d + i_d] = 1;
              }
            }
          break;
        }
      }
      // Not asked for: what `reuse` holds (a new node's rows 0), or continued (below), or 0.
      if (!solve) {
        if (std::none_of(hl.begin(), hl.end(), [](char h) { return h != 0; })) unsolved.push_back({p, c});
        continue;
      }
      for (std::size_t k = 0; k < n_t * n_e; ++k) {
        bool needed = p == 0 && !ht[k];  // (pair 0's top term; every light from below subtracts its top layer's R(k))
        for (std::size_t i_d = 0; i_d < n_d; ++i_d) needed = needed || !hl[k * n_d + i_d];
        if (!needed) continue;
        // A top layer another corner solves already (the dermis ratio's two ends share theirs):
        // solved once.
        const std::array<double, 2> top_geo{v[0], v[1]};
        if (p != 0) {
          const auto same = top_shared.find({top_geo, k});
          if (same != top_shared.end()) {
            top_alias[{static_cast<std::size_t>(p), static_cast<std::size_t>(c), k}] = same->second;
            continue;
          }
          top_shared[{top_geo, k}] = top_jobs.size();
        }
        top_jobs.push_back({p, c, k, ht[k] != 0});
      }
      for (std::size_t k = 0; k < n_t * n_e * n_d; ++k)
        if (!hl[k]) low_jobs.push_back({p, c, k});
    }
  std::mutex m;
  std::size_t done = 0;
  const std::size_t total = top_jobs.size() + low_jobs.size();
  auto tick = [&] {
    if (!progress) return;
    const std::lock_guard<std::mutex> lock(m);
    progress(++done, total);
  };
  // The top layers alone: their R(k) (which the light from below subtracts) and profiles.
  std::vector<std::vector<double>> tops(top_jobs.size()), tops_k(top_jobs.size());
  tbb::parallel_for(std::size_t{0}, top_jobs.size(), [&](std::size_t q) {
    if (util::cancel::requested()) return;
    const Job& jb = top_jobs[q];
    const auto v = values(jb.pair, jb.corner);
    const SkinStackTable geo = geometry(v);
    const std::size_t i_t = jb.k / n_e, i_e = jb.k % n_e;
    tops_k[q] = top_frequencies(geo, tau[i_t], a_e[i_e]);
    const Layer ab = absorber(geo);
    tops[q] = solve(geo, tau[i_t], a_e[i_e], &ab);
    if (jb.pair == 0 && !jb.held) {
      std::vector<double> top, low;
      predicted(v, tau[i_t], a_e[i_e], a_d.front(), top, low);
      const std::vector<double> d = top_offset(tops[q], top, coarse);
      std::copy(d.begin(), d.end(), c_top[0][static_cast<std::size_t>(jb.corner)].begin() + static_cast<std::ptrdiff_t>(jb.k * n_x));
    }
    tick();
  });
  util::cancel::check();
  // Each (pair, corner, tau, a_e)'s top job.
  std::map<std::array<std::size_t, 3>, std::size_t> top_of = top_alias;
  for (std::size_t q = 0; q < top_jobs.size(); ++q)
    top_of[{static_cast<std::size_t>(top_jobs[q].pair), static_cast<std::size_t>(top_jobs[q].corner), top_jobs[q].k}] = q;
  tbb::parallel_for(std::size_t{0}, low_jobs.size(), [&](std::size_t q) {
    if (util::cancel::requested()) return;
    const Job& jb = low_jobs[q];
    const auto v = values(jb.pair, jb.corner);
    const SkinStackTable geo = geometry(v);
    const std::size_t i_d = jb.k % n_d, i_e = (jb.k / n_d) % n_e, i_t = jb.k / (n_d * n_e);
    const std::size_t q_top =
        top_of.at({static_cast<std::size_t>(jb.pair), static_cast<std::size_t>(jb.corner), i_t * n_e + i_e});
    std::vector<double> top, low;
    predicted(v, tau[i_t], a_e[i_e], a_d[i_d], top, low);
    const std::vector<double> d = low_offset(geo, tau[i_t], a_e[i_e], a_d[i_d], tops[q_top], tops_k[q_top], top, low, coarse);
    std::copy(d.begin(), d.end(), c_low[static_cast<std::size_t>(jb.pair)][static_cast<std::size_t>(jb.corner)].begin() + static_cast<std::ptrdiff_t>(jb.k * n_x));
    tick();
  });
  util::cancel::check();
  // A corner neither solved nor held, on a side of an axis that `reuse` had no corners on (it
  // continued the other side's through the base): the other side's corner continued to this end,
  // so that its reads stay what they were (the term is linear in the position in both cases).
  for (const auto& [p, c] : unsolved) {
    const auto pu = static_cast<std::size_t>(p), cu = static_cast<std::size_t>(c);
    for (int which = 0; which < 2 && reuse; ++which) {
      const auto axis = static_cast<std::size_t>(kPairAxes[pu][static_cast<std::size_t>(which)]);
      const std::size_t side = which == 0 ? cu / 2 : cu % 2;
      if (reuse->ends[axis][side] != reuse->base[axis] || ends[axis][1 - side] == base[axis]) continue;
      const std::size_t other = which == 0 ? (cu ^ 2U) : (cu ^ 1U);
      const double f = position(static_cast<int>(axis), 1 - side, ends[axis][side]);
      for (std::size_t i = 0; i < c_top[pu][cu].size(); ++i) c_top[pu][cu][i] = f * c_top[pu][other][i];
      for (std::size_t i = 0; i < c_low[pu][cu].size(); ++i) c_low[pu][cu][i] = f * c_low[pu][other][i];
      provenance += "; " + std::string(kCrossPairNames[pu]) + " at (" + format_number(values(p, c)[static_cast<std::size_t>(kPairAxes[pu][0])]) +
                    ", " + format_number(values(p, c)[static_cast<std::size_t>(kPairAxes[pu][1])]) + ") continued from the other side of " +
                    SkinStackOffsets::kAxisNames[axis];
      break;
    }
  }
}

std::string SkinStackCross::to_csv() const {
  std::ostringstream os;
  os << "# Spectral Skin: cross terms of the skin table's offsets (data/skin_stack_offsets.csv) for two\n"
        "# of g, index and dermis ratio off the table's at once: at each corner (either end of each\n"
        "# axis) ln rho solved by this project's frequency-domain transport solver (FrequencyStack)\n"
        "# minus ln rho of the table with both axes' offsets, on a coarse subset of the offsets' nodes;\n"
        "# their use: include/skin/transport/skin_stack_table.hpp, docs/accurate-solver.md sec. 4.\n";
  os << "# provenance: " << provenance << '\n';
  for (std::size_t a = 0; a < SkinStackOffsets::kAxes; ++a)
    os << "# " << SkinStackOffsets::kAxisNames[a] << ": " << format_number(base[a]) << "\n# "
       << SkinStackOffsets::kAxisNames[a] << "_ends: " << format_number_list({ends[a][0], ends[a][1]}) << '\n';
  os << "# tau: " << format_number_list(tau) << "\n# a_e: " << format_number_list(a_e)
     << "\n# a_d: " << format_number_list(a_d) << "\n# x: " << format_number_list(x) << '\n';
  os << "# Per pair (0: g x eta, 1: g x dermis_ratio, 2: eta x dermis_ratio) and corner: per (tau, a_e)\n"
        "# the top layer's term (a_d = inf; pair 0 only), then per a_d the term of the light from below.\n"
        "# No rows for a corner with an axis at the table's value (its term is 0).\n";
  os << "pair,value_a,value_b,tau,a_e,a_d";
  for (std::size_t i = 0; i < x.size(); ++i) os << ",c_" << i;
  os << '\n';
  for (std::size_t p = 0; p < kPairs; ++p)
    for (std::size_t c = 0; c < 4; ++c) {
      const auto [a, b] = kPairAxes[p];
      const double va = ends[static_cast<std::size_t>(a)][c / 2], vb = ends[static_cast<std::size_t>(b)][c % 2];
      if (va == base[static_cast<std::size_t>(a)] || vb == base[static_cast<std::size_t>(b)]) continue;  // no term, no rows
      write_rows(os, std::to_string(p) + ',' + format_number_list({va, vb}), tau, a_e, a_d, x.size(), c_top[p][c], c_low[p][c]);
    }
  return os.str();
}

SkinStackCross SkinStackCross::parse(std::string_view text, std::string_view source) {
  const std::string src(source);
  const auto meta = csv_metadata(text);
  SkinStackCross c;
  c.provenance = meta.count("provenance") ? meta.at("provenance") : "";
  const double lo[SkinStackOffsets::kAxes] = {0.0, 1.0, 1e-3}, hi[SkinStackOffsets::kAxes] = {0.99, 3.0, 1e3};
  for (std::size_t a = 0; a < SkinStackOffsets::kAxes; ++a) {
    const std::string name = SkinStackOffsets::kAxisNames[a];
    c.base[a] = metadata_number(meta, name, src);
    const std::vector<double> e = metadata_numbers(meta, name + "_ends", src);
    if (!(e.size() == 2 && e[0] >= lo[a] && e[0] <= c.base[a] && c.base[a] <= e[1] && e[1] <= hi[a] && e[0] < e[1]))
      throw InputError(src + ": '" + name + "_ends' must be two different values within [" + format_number(lo[a]) + ", " +
                       format_number(hi[a]) + "], one at or below and one at or above the table's " + format_number(c.base[a]));
    c.ends[a] = {e[0], e[1]};
  }
  read_coarse_nodes(meta, src, c.tau, c.a_e, c.a_d, c.x);
  const Table data = parse_csv(text, src);
  const std::size_t n_x = c.x.size(), n_t = c.tau.size(), n_e = c.a_e.size(), n_d = c.a_d.size();
  if (data.columns.size() != 6 + n_x)
    throw InputError(src + ": expected " + std::to_string(6 + n_x) + " columns, found " + std::to_string(data.columns.size()));
  std::size_t r = 0;
  const std::size_t rows = data.rows();
  for (std::size_t p = 0; p < kPairs; ++p)
    for (std::size_t k4 = 0; k4 < 4; ++k4) {
      const auto [a, b] = kPairAxes[p];
      const double va = c.ends[static_cast<std::size_t>(a)][k4 / 2], vb = c.ends[static_cast<std::size_t>(b)][k4 % 2];
      c.c_top[p][k4].assign(p == 0 ? n_t * n_e * n_x : 0, 0.0);
      c.c_low[p][k4].assign(n_t * n_e * n_d * n_x, 0.0);
      if (va == c.base[static_cast<std::size_t>(a)] || vb == c.base[static_cast<std::size_t>(b)]) continue;  // an axis at the table's value: 0
      std::size_t k = 0, k_top = 0;
      for (std::size_t i_t = 0; i_t < n_t; ++i_t)
        for (std::size_t i_e = 0; i_e < n_e; ++i_e)
          for (std::size_t i_d = p == 0 ? 0 : 1; i_d <= n_d; ++i_d) {
            const bool top = i_d == 0;
            if (r >= rows)
              throw InputError(src + ": the file ends before the rows of " + kCrossPairNames[p] + " = (" + format_number(va) +
                               ", " + format_number(vb) + ")");
            const double want[6] = {static_cast<double>(p), va, vb, c.tau[i_t], c.a_e[i_e], top ? kInfinity : c.a_d[i_d - 1]};
            for (std::size_t col = 0; col < 6; ++col) {
              const double v = data.data[col][r];
              if (!(want[col] == kInfinity ? v == kInfinity : (col == 0 ? v == want[col] : std::abs(v / want[col] - 1) <= 1e-6)))
                throw InputError(src + ": row " + std::to_string(r + 1) + " is not node (pair, value_a, value_b, tau, a_e, a_d) = (" +
                                 std::to_string(p) + ", " + format_number(va) + ", " + format_number(vb) + ", " +
                                 format_number(want[3]) + ", " + format_number(want[4]) + ", " + format_number(want[5]) + ")");
            }
            double* out = top ? c.c_top[p][k4].data() + k_top++ * n_x : c.c_low[p][k4].data() + k++ * n_x;
            for (std::size_t i = 0; i < n_x; ++i) {
              const double v = data.data[6 + i][r];
              if (!(std::abs(v) <= kMaxOffset))
                throw InputError(src + ": row " + std::to_string(r + 1) + ", column " + data.columns[6 + i] + " = " +
                                 format_number(v) + " is not a finite number within " + format_number(kMaxOffset) + " of 0");
              out[i] = v;
            }
            ++r;
          }
    }
  if (r != rows) throw InputError(src + ": " + std::to_string(rows - r) + " row(s) after its last node");
  return c;
}

double SkinStackCross::position(int axis, std::size_t side, double v) const {
  const auto a = static_cast<std::size_t>(axis);
  return (axis_variable(axis, v) - axis_variable(axis, base[a])) / (axis_variable(axis, ends[a][side]) - axis_variable(axis, base[a]));
}

double SkinStackCross::reach(int axis, std::size_t side) const {
  const auto a = static_cast<std::size_t>(axis);
  if (ends[a][side] != base[a] || ends[a][1 - side] == base[a]) return ends[a][side];
  // The other side's end mirrored through the base in the axis' variable (ln(1 - g), the index,
  // ln ratio).
  return axis_value(axis, 2 * axis_variable(axis, base[a]) - axis_variable(axis, ends[a][1 - side]));
}

void SkinStackCross::add(double t, double ae, double ad, const std::array<double, SkinStackOffsets::kAxes>& v,
                         std::vector<double>& dt, std::vector<double>& dl) const {
  // Per axis: the corners' side (0 below the base, 1 above) and the position from the base to
  // that end; on a side without corners, the other side's, continued linearly through the base (a
  // negative position; gap() keeps it within -1).
  std::array<std::size_t, SkinStackOffsets::kAxes> side{};
  std::array<double, SkinStackOffsets::kAxes> w{};
  for (std::size_t a = 0; a < SkinStackOffsets::kAxes; ++a) {
    side[a] = v[a] > base[a] ? 1 : 0;
    if (ends[a][side[a]] == base[a]) side[a] = 1 - side[a];
    if (v[a] == base[a] || ends[a][side[a]] == base[a]) continue;  // (no corners on either side: no term)
    w[a] = position(static_cast<int>(a), side[a], v[a]);
  }
  const std::size_t n_x = x.size(), n_e = a_e.size(), n_d = a_d.size();
  bool any = false;
  for (const auto& [a, b] : kPairAxes) any = any || (w[static_cast<std::size_t>(a)] != 0 && w[static_cast<std::size_t>(b)] != 0);
  if (!any) return;
  const Lagrange4Stencil st_top = tau_stencil_held(tau, t, true);
  const Lagrange4Stencil st = tau_stencil_held(tau, t, false);
  const Lagrange4Stencil se = a_e_stencil_held(a_e, ae);
  const Lagrange4Stencil sd = lagrange4_stencil(mapped(a_d, sqrt_of), std::sqrt(ad));
  // The terms, added to dt and dl at the end: beyond x = kCrossHeldFrom they keep their value
  // there. Farther out a bright dermis' tail at one node meets the floor at its neighbours (the
  // stencil spans a_d up to 30 times apart, whose tails fall at rates several times apart), and
  // the interpolated term is noise: a bright epidermis over a dermis of ratio 0.2 with index 1.55
  // and g 0.78 (caucasian, 0.16 mm, 740 nm) read its tail beyond x = 100 up to 10^3 times the solve,
  // 3 % of R_d, which the scaling to R_d took from every radius (4.3 % off the solver; held, 1 %).
  std::vector<double> ct_sum(n_x, 0.0), cl_sum(n_x, 0.0);
  for (std::size_t p = 0; p < kPairs; ++p) {
    const auto a = static_cast<std::size_t>(kPairAxes[p][0]), b = static_cast<std::size_t>(kPairAxes[p][1]);
    const double wp = w[a] * w[b];
    if (wp == 0) continue;
    const std::size_t corner = 2 * side[a] + side[b];
    const std::vector<double>& ct = c_top[p][corner];
    const std::vector<double>& cl = c_low[p][corner];
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t e = 0; e < 4; ++e) {
        if (!ct.empty()) {
          const double wt = wp * st_top.weights[i] * se.weights[e];
          const double* r = ct.data() + ((st_top.first + i) * n_e + se.first + e) * n_x;
          for (std::size_t m = 0; m < n_x; ++m) ct_sum[m] += wt * r[m];
        }
        for (std::size_t l = 0; l < 4; ++l) {
          const double wl = wp * st.weights[i] * se.weights[e] * sd.weights[l];
          const double* r = cl.data() + (((st.first + i) * n_e + se.first + e) * n_d + sd.first + l) * n_x;
          for (std::size_t m = 0; m < n_x; ++m) cl_sum[m] += wl * r[m];
        }
      }
  }
  std::size_t last = 0;
  while (last + 1 < n_x && x[last + 1] <= kCrossHeldFrom) ++last;
  for (std::size_t m = 0; m < n_x; ++m) {
    dt[m] += ct_sum[std::min(m, last)];
    dl[m] += cl_sum[std::min(m, last)];
  }
}

}  // namespace skin::transport::accurate
