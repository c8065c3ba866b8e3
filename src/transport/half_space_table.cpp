// HalfSpaceTable: FrequencyStack's profiles of absorbing half-spaces over (a, g, eta), tabulated
// (docs/accurate-solver.md, sec. 4).
#include "skin/transport/half_space_table.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <sstream>

#include "skin/transport/accurate.hpp"
#include "skin/transport/skin_stack_table.hpp"
#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"
#include "skin/util/interpolation.hpp"
#include "skin/util/table.hpp"
#include "skin_tables_core.hpp"

namespace skin::transport::accurate {

using skin::physics::LayerStack;
using skin::util::InputError;
using skin::util::format_number;
using skin::util::format_number_list;
using namespace tables;

namespace {
double minus_ln_one_minus(double v) { return -std::log(1 - v); }  // increasing in g
// A node's values count down to this share of its peak (at the first x node); below, the
// solve's inversion is near its noise (its floor kFloor is 1e-13).
constexpr double kReliable = 1e-10;
}  // namespace

HalfSpaceTable HalfSpaceTable::default_nodes() {
  HalfSpaceTable t;
  // a: 0.25 apart in sqrt a up to 4 (a 0.0625-4), then 0.5 apart up to 42.25. The half-spaces the
  // skin domain asks for (a dark epidermis that hides the dermis; 2000 sets at 41 wavelengths,
  // seed 7) have a 0.097-38.6, most of them 4-30. (Measured by 4-point Lagrange at a node
  // interval's middle against a solve there: sqrt a 0.5 apart at a 12-25 within 0.14 % where R is
  // above 1e-4 of its peak.)
  for (int j = 1; j <= 8; ++j) t.a.push_back(std::pow(0.25 * j, 2));
  for (int j = 1; j <= 9; ++j) t.a.push_back(std::pow(2.0 + 0.5 * j, 2));
  // g: 0.05 apart to 0.9 (0.11 % midway, measured as above at a 20), then 0.015 and 0.01 apart to
  // the domain's top 0.97; interpolated in ln(1 - g). (With 0.93, 0.95 and 0.97 alone, 40 random
  // half-spaces read median 0.33 % off the solver above 1e-4 of the peak, but those with g
  // 0.95-0.96 up to 6.5 % near the beam, at x 0.004.)
  t.g = {0.7, 0.75, 0.8, 0.85, 0.9, 0.915, 0.93, 0.94, 0.95, 0.96, 0.97};
  // The index over the skin domain's 1.33-1.55, 0.055 apart (0.026 % midway).
  t.eta = {1.33, 1.385, 1.44, 1.495, 1.55};
  // The skin table's x nodes: 1e-3 to 421, 16 per decade.
  for (int i = 0; i <= 90; ++i) t.x.push_back(1e-3 * std::pow(10.0, i / 16.0));
  return t;
}

std::vector<double> HalfSpaceTable::solve(double a_v, double g_v, double eta_v) const {
  return floored_log(tables::solve(x, eta_v, g_v, physics::kInfinity, a_v, nullptr));
}

void HalfSpaceTable::compute(const util::ProgressCallback& progress, const HalfSpaceTable* reuse) {
  if (reuse && !same_nodes(reuse->x, x)) throw InputError("reuse: the table to reuse has other x nodes than the one computed");
  const std::size_t n_a = a.size(), n_e = eta.size(), n_x = x.size(), n = g.size() * n_e * n_a;
  ln_rho.assign(n * n_x, 0.0);
  // Per node: its row in `reuse`, or npos (solved).
  auto index_in = [](const std::vector<double>& nodes, double v) {
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (same_node(nodes[i], v)) return i;
    return std::string::npos;
  };
  std::mutex m;
  std::size_t done = 0;
  // The slowest nodes first (the highest g: ~15 times a node at g 0.7), so that the last ones
  // keep both cores busy.
  std::vector<std::size_t> order(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = n - 1 - k;
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t o) {
    if (util::cancel::requested()) return;  // thrown below
    const std::size_t k = order[o], i_a = k % n_a, i_e = (k / n_a) % n_e, i_g = k / (n_a * n_e);
    double* out = ln_rho.data() + k * n_x;
    std::size_t from = std::string::npos;
    if (reuse) {
      const std::size_t ra = index_in(reuse->a, a[i_a]), re = index_in(reuse->eta, eta[i_e]), rg = index_in(reuse->g, g[i_g]);
      if (ra != std::string::npos && re != std::string::npos && rg != std::string::npos)
        from = (rg * reuse->eta.size() + re) * reuse->a.size() + ra;
    }
    if (from != std::string::npos) {
      std::copy_n(reuse->ln_rho.data() + from * n_x, n_x, out);
    } else {
      const std::vector<double> v = solve(a[i_a], g[i_g], eta[i_e]);
      std::copy(v.begin(), v.end(), out);
    }
    if (progress) {
      const std::lock_guard<std::mutex> lock(m);
      progress(++done, n);
    }
  });
  util::cancel::check();
}

std::string HalfSpaceTable::to_csv() const {
  std::ostringstream os;
  os << "# Spectral Skin: radial profiles of absorbing half-spaces under air in units of their reduced\n"
        "# scattering s (a = sigma_a / s, x = r s, R(r) = s^2 rho(x)), computed by this project's\n"
        "# frequency-domain transport solver (FrequencyStack); the columns and their use:\n"
        "# include/skin/transport/half_space_table.hpp, docs/accurate-solver.md sec. 4.\n";
  os << "# provenance: " << provenance << '\n';
  os << "# a: " << format_number_list(a) << "\n# g: " << format_number_list(g) << "\n# eta: " << format_number_list(eta)
     << "\n# x: " << format_number_list(x) << '\n';
  os << "g,eta,a";
  for (std::size_t i = 0; i < x.size(); ++i) os << ",ln_rho_" << i;
  os << '\n';
  char buf[32];
  std::size_t k = 0;
  for (double gv : g)
    for (double e : eta)
      for (double av : a) {
        os << format_number_list({gv, e, av});
        for (std::size_t i = 0; i < x.size(); ++i) {
          std::snprintf(buf, sizeof buf, ",%.4f", ln_rho[k * x.size() + i]);
          os << buf;
        }
        os << '\n';
        ++k;
      }
  return os.str();
}

HalfSpaceTable HalfSpaceTable::parse(std::string_view text, std::string_view source) {
  const std::string src(source);
  const auto meta = util::csv_metadata(text);
  HalfSpaceTable t;
  t.provenance = meta.count("provenance") ? meta.at("provenance") : "";
  t.a = util::metadata_numbers(meta, "a", src);
  t.g = util::metadata_numbers(meta, "g", src);
  t.eta = util::metadata_numbers(meta, "eta", src);
  t.x = util::metadata_numbers(meta, "x", src);
  struct Axis {
    const std::vector<double>* v;
    const char* key;
    double lo, hi;
  };
  for (const Axis& ax : {Axis{&t.a, "a", 1e-9, 1e9}, Axis{&t.g, "g", 0.0, 0.999}, Axis{&t.eta, "eta", 1.0, 3.0},
                         Axis{&t.x, "x", 1e-9, 1e9}}) {
    const std::vector<double>& v = *ax.v;
    if (v.size() < 4) throw InputError(src + ": '" + ax.key + "' needs at least 4 nodes");
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!(v[i] >= ax.lo && v[i] <= ax.hi) || (i > 0 && !(v[i] > v[i - 1])))
        throw InputError(src + ": '" + ax.key + "' must lie within [" + format_number(ax.lo) + ", " +
                         format_number(ax.hi) + "] and increase");
  }
  check_x_nodes(t.x, src);
  const util::Table data = util::parse_csv(text, src);
  const std::size_t n_x = t.x.size(), n_a = t.a.size(), n_e = t.eta.size(), rows = t.g.size() * n_e * n_a;
  if (data.columns.size() != 3 + n_x)
    throw InputError(src + ": expected " + std::to_string(3 + n_x) + " columns, found " + std::to_string(data.columns.size()));
  if (data.rows() != rows)
    throw InputError(src + ": expected " + std::to_string(rows) + " rows (g x eta x a), found " + std::to_string(data.rows()));
  t.ln_rho.resize(rows * n_x);
  for (std::size_t r = 0; r < rows; ++r) {
    const double want[3] = {t.g[r / (n_a * n_e)], t.eta[(r / n_a) % n_e], t.a[r % n_a]};
    for (std::size_t c = 0; c < 3; ++c)
      if (!(std::abs(data.data[c][r] / want[c] - 1) <= 1e-6))
        throw InputError(src + ": row " + std::to_string(r + 1) + " is not node (g, eta, a) = (" + format_number(want[0]) +
                         ", " + format_number(want[1]) + ", " + format_number(want[2]) + ")");
    double* out = t.ln_rho.data() + r * n_x;
    for (std::size_t i = 0; i < n_x; ++i) out[i] = data.data[3 + i][r];
    check_row(out, n_x, src, r + 1, data.columns);
  }
  return t;
}

const HalfSpaceTable& HalfSpaceTable::builtin() {
  static const HalfSpaceTable t = parse(util::data::embedded("half_space_profiles.csv"), "half_space_profiles.csv");
  return t;
}

std::string HalfSpaceTable::gap(double a_v, double g_v, double eta_v) const {
  auto inside = [](const std::vector<double>& v, double u) { return u >= v.front() && u <= v.back(); };
  if (!inside(a, a_v))
    return "sigma_a / sigma_s' = " + format_number(a_v) + " is outside the half-space table's " + format_number(a.front()) +
           "-" + format_number(a.back());
  if (!inside(g, g_v))
    return "g = " + format_number(g_v) + " is outside the half-space table's " + format_number(g.front()) + "-" +
           format_number(g.back());
  if (!inside(eta, eta_v))
    return "index " + format_number(eta_v) + " is outside the half-space table's " + format_number(eta.front()) + "-" +
           format_number(eta.back());
  return "";
}

std::string HalfSpaceTable::gap(const LayerStack& stack) const {
  if (stack.layers.empty()) return "no layer";
  if (stack.eta_above != 1.0) return "a medium other than air above";
  const physics::Layer& t = stack.layers.front();
  const bool nearly = stack.layers.size() > 1 && AccurateStack::nearly_hides_below(stack);
  if (stack.layers.size() == 1 ? !t.semi_infinite() : !(AccurateStack::hides_below(stack) || nearly))
    return stack.layers.size() == 1 ? "a slab, not a half-space" : "its top layer does not hide the rest";
  if (!(t.sigma_s_prime > 0) || !(t.sigma_a >= 0)) return "a layer without scattering";
  std::string why = gap(t.sigma_a / t.sigma_s_prime, t.g, t.eta);
  if (!why.empty() || !nearly) return why;
  // Nearly hidden: the lower layer's half-space is read too.
  const physics::Layer& b = stack.layers.back();
  if (!(b.sigma_s_prime > 0) || !(b.sigma_a >= 0)) return "a layer without scattering";
  why = gap(b.sigma_a / b.sigma_s_prime, b.g, b.eta);
  return why.empty() ? why : "the lower layer (its top layer nearly hides it): " + why;
}

std::vector<double> HalfSpaceTable::ln_rho_at(double a_v, double g_v, double eta_v) const {
  const util::Lagrange4Stencil sa = util::lagrange4_stencil(mapped(a, sqrt_of), std::sqrt(a_v));
  const util::Lagrange4Stencil sg = util::lagrange4_stencil(mapped(g, minus_ln_one_minus), -std::log(1 - g_v));
  const util::Lagrange4Stencil se = util::lagrange4_stencil(eta, eta_v);
  const std::size_t n_x = x.size(), n_a = a.size(), n_e = eta.size();
  std::vector<double> out(n_x, 0.0);
  std::size_t reliable = n_x;  // the first x node where a node of the stencil nears its floor
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j)
      for (std::size_t l = 0; l < 4; ++l) {
        const double w = sg.weights[i] * se.weights[j] * sa.weights[l];
        const double* v = ln_rho.data() + (((sg.first + i) * n_e + se.first + j) * n_a + sa.first + l) * n_x;
        for (std::size_t m = 0; m < n_x; ++m) out[m] += w * v[m];
        if (w == 0) continue;
        const double near_floor = *std::max_element(v, v + n_x) + std::log(kReliable);
        for (std::size_t m = 0; m < reliable; ++m)
          if (v[m] < near_floor) {
            reliable = m;
            break;
          }
      }
  // Beyond, ln rho continues linearly in x from the last two reliable nodes (falling): near their
  // floor the nodes' values are the solve's noise, and a stencil that mixes them with the floor
  // bends far below the profile (a dark epidermis hiding the dermis, a 15.45: -71 % to -99 % off
  // 3 x 10^8 photons at x 0.68-0.78; continued, see docs/accurate-solver.md sec. 4).
  if (reliable >= 2 && reliable < n_x) {
    const std::size_t m1 = reliable - 1, m0 = reliable - 2;
    const double slope = std::min(0.0, (out[m1] - out[m0]) / (x[m1] - x[m0]));
    for (std::size_t m = reliable; m < n_x; ++m) out[m] = out[m1] + slope * (x[m] - x[m1]);
  }
  for (double& v : out) v = clamp_ln(v);
  return out;
}

}  // namespace skin::transport::accurate
