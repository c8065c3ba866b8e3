#include "skin/transport/skin_stack_table.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <numbers>
#include <sstream>

#include "skin/transport/accurate.hpp"
#include "skin/transport/profile.hpp"
#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"
#include "skin/util/interpolation.hpp"
#include "skin/util/table.hpp"

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

namespace {

constexpr double kFloor = 1e-13;  // of a node's peak
// A table's ln rho (rho in units of s^2) lies within kMaxLnRho of 0 (the built-in table's within
// -27.5 and 2.8), and each row within -ln kFloor = 29.93 of its own peak: parse() refuses other
// values. Interpolated values are clamped to kMaxLnRho + kOvershoot, so that exp() of them is finite
// whatever the weights (4-point Lagrange weights grow without bound on nodes nearly together): a
// table that parses gives a finite, non-negative profile by construction. Neither bound is reached
// by interpolation between real nodes (an overshoot of 30 e-folds is not a smooth profile's).
constexpr double kMaxLnRho = 100, kOvershoot = 30, kMaxRowSpan = 29.94;
double clamp_ln(double v) {
  constexpr double lim = kMaxLnRho + kOvershoot;
  return std::isnan(v) ? -lim : std::clamp(v, -lim, lim);
}

std::vector<double> mapped(const std::vector<double>& v, double (*f)(double)) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = f(v[i]);
  return out;
}
double log_of(double v) { return std::log(v); }
double sqrt_of(double v) { return std::sqrt(v); }
// ln(e^a + e^b)
double log_sum(double a, double b) { return std::max(a, b) + std::log1p(std::exp(-std::abs(a - b))); }
// ln R, floored at kFloor of its peak (the table's values).
std::vector<double> floored_log(std::vector<double> R) {
  const double peak = *std::max_element(R.begin(), R.end());
  for (double& v : R) v = std::log(std::max(v, kFloor * peak));
  return R;
}

}  // namespace

SkinStackTable SkinStackTable::default_nodes() {
  SkinStackTable t;
  for (int k = -8; k <= 2; ++k) t.tau.push_back(2.0 * std::pow(1.5, k));
  // a: four per decade from 0.004 to 0.4, then evenly in sqrt(a) (0.25 apart, then 0.5).
  std::vector<double> a;
  for (int k = 0; k <= 8; ++k) a.push_back(0.004 * std::pow(10.0, k / 4.0));
  const double u0 = std::sqrt(a.back());
  t.a_e = a;
  for (int j = 1; j <= 8; ++j) a.push_back(std::pow(u0 + 0.25 * j, 2));
  for (int j = 1; j <= 2; ++j) a.push_back(std::pow(u0 + 2.0 + 0.5 * j, 2));
  t.a_d = a;
  // The top layer twice as dense beyond 0.4 (0.125 apart in sqrt a, up to 6.93: every preset at
  // 380-780 nm): a dark epidermis' far field is a sum of paths whose attenuation differs by
  // several e-folds between nodes 0.25 apart (90 % off midway at a_e 0.57 with those).
  for (int j = 1; j <= 16; ++j) t.a_e.push_back(std::pow(u0 + 0.125 * j, 2));
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
// rho at the x nodes of the table's geometry with this lower layer (FrequencyStack; in units of
// s: k0 = 0.3 / 15, the resolution FrequencyStack has on the most scattering skin, 5 % at 10 mm
// otherwise: its nodes are fixed in rad/mm, so in units of s = 1 /mm they would be those of a
// stack with s = 1 /mm, and the skin's s is 4-15 /mm).
std::vector<double> solve(const SkinStackTable& t, double tau_v, double a_e_v, const Layer* below) {
  LayerStack st;
  st.eta_above = 1.0;
  st.layers.push_back({a_e_v, 1.0, tau_v, t.eta, t.g});
  if (below) st.layers.push_back(*below);
  FrequencyProfileOptions o;
  o.k0 = 0.3 / 15.0;
  const FrequencyStack f(st, o);
  ProfileSolver solver(RadialGrid::from(t.x));
  return solver.profile(f);
}
// The top layer over an index-matched absorber (sigma_a = 1, sigma_s' = 1e-9 in units of s: no
// light comes back from below).
Layer absorber(const SkinStackTable& t) { return {1.0, 1e-9, kInfinity, t.eta, t.g}; }

Layer dermis(const SkinStackTable& t, double a_d_v) { return {a_d_v, t.dermis_ratio, kInfinity, t.eta, t.g}; }
}  // namespace

std::vector<double> SkinStackTable::solve_node(double tau_v, double a_e_v, double a_d_v) const {
  const Layer d = dermis(*this, a_d_v);
  return floored_log(solve(*this, tau_v, a_e_v, &d));
}

std::vector<double> SkinStackTable::solve_top(double tau_v, double a_e_v) const {
  const Layer a = absorber(*this);
  return floored_log(solve(*this, tau_v, a_e_v, &a));
}

std::vector<double> SkinStackTable::solve_half_space(double a_v) const {
  return floored_log(solve(*this, kInfinity, a_v, nullptr));
}

namespace {
// Node values equal to a relative 1e-6 (a table read back holds 7 digits).
bool same_node(double a, double b) { return std::abs(a - b) <= 1e-6 * std::abs(b); }
// Index of v among nodes, or npos.
std::size_t node_index(const std::vector<double>& nodes, double v) {
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (same_node(nodes[i], v)) return i;
  return std::string::npos;
}
bool same_nodes(const std::vector<double>& a, const std::vector<double>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), same_node);
}
}  // namespace

void SkinStackTable::compute(const ProgressCallback& progress, const SkinStackTable* reuse) {
  const std::size_t n_e = a_e.size(), n_d = a_d.size(), n_x = x.size();
  if (reuse && !(reuse->eta == eta && reuse->g == g && reuse->dermis_ratio == dermis_ratio &&
                 same_nodes(reuse->a_d, a_d) && same_nodes(reuse->x, x)))
    throw InputError("reuse: the table to reuse has another geometry, a_d or x nodes than the one computed");
  const bool reuse_half = reuse && same_nodes(reuse->a_h, a_h);
  // Per (tau, a_e): its row in `reuse`, or npos (solved).
  std::vector<std::size_t> from(tau.size() * n_e, std::string::npos);
  if (reuse)
    for (std::size_t i_t = 0; i_t < tau.size(); ++i_t)
      for (std::size_t i_e = 0; i_e < n_e; ++i_e) {
        const std::size_t r_t = node_index(reuse->tau, tau[i_t]), r_e = node_index(reuse->a_e, a_e[i_e]);
        if (r_t != std::string::npos && r_e != std::string::npos) from[i_t * n_e + i_e] = r_t * reuse->a_e.size() + r_e;
      }
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
  // The top layers first (each lower-layer node subtracts its top layer's profile).
  std::vector<std::vector<double>> top(tau.size() * n_e);
  tbb::parallel_for(std::size_t{0}, tau.size() * n_e, [&](std::size_t k) {
    if (util::cancel::requested()) return;  // thrown below
    if (from[k] != std::string::npos) {
      const auto src = reuse->ln_rho_top.begin() + static_cast<std::ptrdiff_t>(from[k] * n_x);
      std::copy(src, src + static_cast<std::ptrdiff_t>(n_x), ln_rho_top.begin() + static_cast<std::ptrdiff_t>(k * n_x));
      const auto rows = reuse->ln_rho.begin() + static_cast<std::ptrdiff_t>(from[k] * n_d * n_x);
      std::copy(rows, rows + static_cast<std::ptrdiff_t>(n_d * n_x), ln_rho.begin() + static_cast<std::ptrdiff_t>(k * n_d * n_x));
      for (std::size_t i = 0; i <= n_d; ++i) tick();
      return;
    }
    const Layer a = absorber(*this);
    top[k] = solve(*this, tau[k / n_e], a_e[k % n_e], &a);
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
    if (from[i_t * n_e + i_e] != std::string::npos) return;  // copied with its top layer
    const Layer d = dermis(*this, a_d[i_d]);
    const std::vector<double> R = solve(*this, tau[i_t], a_e[i_e], &d);
    const std::vector<double>& T = top[i_t * n_e + i_e];
    const double peak = *std::max_element(R.begin(), R.end());
    for (std::size_t i = 0; i < n_x; ++i)
      ln_rho[k * n_x + i] = std::log(std::max(R[i] - T[i], kFloor * peak));
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
        "# reaches the lower layer), then per a_d the light that reached it: ln(rho - rho_top).\n"
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
  // Simpson's rule and the cubic in ln x need an odd number of x nodes, evenly spaced in ln x.
  const double h = std::log(t.x.back() / t.x.front()) / static_cast<double>(t.x.size() - 1);
  for (std::size_t i = 1; i < t.x.size(); ++i)
    if (t.x.size() % 2 == 0 || !(std::abs(std::log(t.x[i] / t.x[i - 1]) / h - 1) <= 1e-5))
      throw InputError(src + ": 'x' must be an odd number of nodes evenly spaced in ln x");
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
    for (std::size_t i = 0; i < n_x; ++i) {
      const double v = data.data[3 + i][r];
      if (!(std::abs(v) <= kMaxLnRho))
        throw InputError(src + ": row " + std::to_string(r + 1) + ", column " + data.columns[3 + i] + " = " +
                         format_number(v) + " is not a finite number within " + format_number(kMaxLnRho) +
                         " of 0 (ln rho)");
      out[i] = v;
    }
    const auto [lo, hi] = std::minmax_element(out, out + n_x);
    if (!(*hi - *lo <= kMaxRowSpan))
      throw InputError(src + ": row " + std::to_string(r + 1) + " spans " + format_number(*hi - *lo) +
                       " in ln rho; allowed: at most " + format_number(kMaxRowSpan) +
                       " (the table's floor, 1e-13 of a row's peak)");
  }
  return t;
}

const SkinStackTable& SkinStackTable::builtin() {
  static const SkinStackTable t = parse(util::data::embedded("skin_stack_profiles.csv"), "skin_stack_profiles.csv");
  return t;
}

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
  if (e.eta != eta || d.eta != eta) return "index is not the skin table's " + format_number(eta);
  if (e.g != g || d.g != g) return "g is not the skin table's " + format_number(g);
  if (e.semi_infinite() || !d.semi_infinite()) return "not a finite layer over a half-space";
  const double s = e.sigma_s_prime;
  if (!(s > 0) || !(std::abs(d.sigma_s_prime / s - dermis_ratio) <= 1e-9 * dermis_ratio))
    return "the lower layer's sigma_s' is not " + format_number(dermis_ratio) + " x the top layer's";
  const double t = s * e.thickness, ae = e.sigma_a / s, ad = d.sigma_a / s;
  if (!inside(tau, t)) return "sigma_s' d = " + format_number(t) + " is outside the skin table's [" + format_number(tau.front()) + ", " + format_number(tau.back()) + "]";
  if (!inside(a_e, ae)) return "top sigma_a / sigma_s' = " + format_number(ae) + " is outside the skin table's [" + format_number(a_e.front()) + ", " + format_number(a_e.back()) + "]";
  if (!inside(a_d, ad)) return "lower sigma_a / top sigma_s' = " + format_number(ad) + " is outside the skin table's [" + format_number(a_d.front()) + ", " + format_number(a_d.back()) + "]";
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

std::vector<double> SkinStackTable::ln_rho_at(double t, double ae, double ad) const {
  // The top layer alone in ln tau (as a power of its thickness near the beam); the light from
  // below in tau (it crosses the top layer twice: ln rho falls linearly in tau).
  const Lagrange4Stencil st_top = lagrange4_stencil(mapped(tau, log_of), std::log(t));
  const Lagrange4Stencil st = lagrange4_stencil(tau, t);
  const Lagrange4Stencil se = lagrange4_stencil(mapped(a_e, sqrt_of), std::sqrt(ae));
  const Lagrange4Stencil sd = lagrange4_stencil(mapped(a_d, sqrt_of), std::sqrt(ad));
  const std::size_t n_x = x.size();
  std::vector<double> top(n_x, 0.0), below(n_x, 0.0);
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
  for (std::size_t m = 0; m < n_x; ++m) top[m] = clamp_ln(log_sum(clamp_ln(top[m]), clamp_ln(below[m])));
  return top;
}

SkinStackProfile::SkinStackProfile(const SkinStackTable& table, const LayerStack& stack, double R_d)
    : table_(&table) {
  const Layer& e = stack.layers.at(0);
  s_ = e.sigma_s_prime;
  ln_rho_ = stack.layers.size() == 1
                ? table.ln_rho_half_space_at(e.sigma_a / s_)
                : table.ln_rho_at(s_ * e.thickness, e.sigma_a / s_, stack.layers.at(1).sigma_a / s_);
  ln_x_ = mapped(table.x, log_of);
  const std::size_t n = ln_x_.size();
  h_ = (ln_x_.back() - ln_x_.front()) / static_cast<double>(n - 1);
  cutoff_ = *std::max_element(ln_rho_.begin(), ln_rho_.end()) + std::log(10 * kFloor);
  // Near the beam rho grows like a power of 1 / x (single scattering: 1 / x): continued from the
  // first two nodes down to a tenth of the first x node, flat below.
  power_ = std::clamp((ln_rho_[1] - ln_rho_[0]) / h_, -1.9, 0.0);
  // Beyond the last node: ln rho linear in x, falling (0 if it does not fall).
  const double x1 = table.x[n - 1];
  decay_ = std::max(0.0, -(ln_rho_[n - 1] - ln_rho_[n - 2]) / (x1 - table.x[n - 2]));
  // 2 pi int x rho dx of exactly what operator() returns: Simpson on the even ln x grid (as
  // 2 pi int x^2 rho d(ln x)), the power law and the flat disc below it, the exponential beyond.
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double f = ln_rho_[i] < cutoff_ ? 0.0 : std::exp(2 * ln_x_[i] + ln_rho_[i]);
    sum += ((i == 0 || i == n - 1) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0)) * f;
  }
  double integral = 2 * std::numbers::pi * sum * h_ / 3.0;
  const double x0 = table.x.front(), xf = x0 / 10, rho0 = std::exp(ln_rho_[0]);
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
  const double x = r * s_, x0 = table_->x.front();
  if (x < x0) return scale_ * std::exp(ln_rho_[0]) * std::pow(std::max(x, x0 / 10) / x0, power_);
  const double lx = std::log(x);
  if (lx >= ln_x_.back()) {
    if (decay_ == 0 || ln_rho_[n - 1] < cutoff_) return 0.0;
    return scale_ * std::exp(ln_rho_[n - 1] - decay_ * (x - table_->x[n - 1]));
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

}  // namespace skin::transport::accurate
